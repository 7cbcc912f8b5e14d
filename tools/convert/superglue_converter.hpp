#pragma once
// SuperGlue ONNX -> model pack. Layers are found by graph structure (BatchNorm already folded, initializer names
// generic): the keypoint-encoder Conv1d chains (3 -> ... -> D, ReLU between) added to the descriptors, then per
// attentional layer the residual Add(x, MLP(Concat(x, merge(attention(q(x), k(src), v(src)))))) of each keypoint
// set, self when src is the same set and cross when it is the other one, until the final projection feeding the
// score Einsum; the dustbin score is the scalar expanded next to the scores. The layer count is read from the
// graph. Both keypoint sets must use identical weights (they are one module in SuperGlue).
//
// Pack contents (kind superglue), all Conv1d as "L.weight" [O, I] layout "oi" and "L.bias" [O] layout "dense",
// each as fp32 and fp16:
//   kenc.<i>                          keypoint encoder, i = 0 .. widths (input [x, y, score])
//   gnn.<l>.{q,k,v,merge,mlp0,mlp1}   attentional layer l = 0 .. gnn_layers-1 (mlp0: 2D -> 2D, mlp1: 2D -> D)
//   final_proj
// q/k/v output channels (and merge input channels) keep SuperGlue's order c = d * heads + h ("dim_major").
// Hyper-parameters: descriptor_dim, gnn_layers, heads, keypoint_encoder [hidden widths], gnn_layer_types
// ("self,cross,..."), sinkhorn_iterations, bin_score, attention_channel_order ("dim_major"), source.
#include "io/model_pack.hpp"
#include "tools/convert/onnx_graph.hpp"

namespace vkvo::convert {

io::ModelPackWriter convert_superglue(const OnnxGraph& graph);

}  // namespace vkvo::convert
