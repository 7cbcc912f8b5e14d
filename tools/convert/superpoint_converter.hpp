#pragma once
// SuperPoint ONNX -> model pack. The twelve convolutions are found by walking the graph from the image input
// (Conv/Relu/MaxPool encoder, then the detector head feeding Softmax and the descriptor head feeding the L2 norm),
// never by initializer names, and checked against the SuperPoint architecture.
//
// Pack contents (kind superpoint): for L in conv1a conv1b conv2a conv2b conv3a conv3b conv4a conv4b convPa convPb
// convDa convDb: "L.weight" shape [O, I, KH, KW] and "L.bias" shape [O], both in layout "o4"
// (runtime/tensor_layout.hpp; convPb's 65 outputs padded to 68), each as fp32 and fp16.
// Hyper-parameters: descriptor_dim, detector_channels (65), cell (8), encoder_widths [64, 64, 128, 128], source.
#include "io/model_pack.hpp"
#include "tools/convert/onnx_graph.hpp"

namespace vkvo::convert {

io::ModelPackWriter convert_superpoint(const OnnxGraph& graph);

}  // namespace vkvo::convert
