#!/usr/bin/env python3
"""What 16-bit storage costs SuperPoint's dense outputs, against the golden PyTorch reference
(../shared/golden/superpoint, real Magic Leap weights), simulated in float64 with chosen tensors rounded to fp16.

Two questions, each a set of variants:
- Why fp16s stores the convolution weights in fp32 and the input as exact pixel values (runtime/ops.hpp,
  conv_weight_precision; shaders/superpoint_input.comp): direct convolutions with 16-bit activations, with and
  without 16-bit weights (in every layer, or in all but the full-resolution ones) and a 16-bit pixel / 255 input.
- Why vkvo's Winograd convolutions are fp32 only: each 3x3 convolution but conv1a (the stem, computed in the input
  transform) runs as F(m x m, 3x3) with the shaders' transform matrices, rounding to fp16 the transformed input
  V = B^T d B, the transformed weights U = G g G^T and/or the GEMMs' products M.
Prints the dense-score max abs error and the worst descriptor cosine per variant; the golden README's fp16
acceptance is <= 2e-3 and >= 0.999.

    /usr/bin/python3 tools/superpoint_fp16_error.py [--data ../shared] [CASE ...]   (default: the two EuRoC crops)
Needs numpy, torch and PIL (Debian: python3-numpy, python3-torch, python3-pil); reads the ONNX file itself.
A full-size case takes about a minute per variant on 2 cores.
"""
import argparse
import os

import numpy as np
import torch
import torch.nn.functional as F
from PIL import Image

# Winograd matrices (interpolation points as in shaders/include/winograd_f43.glsl, winograd_f63.glsl).
T = lambda rows: torch.tensor(rows, dtype=torch.float64)
MATRICES = {
    4: dict(BT=T([[4, 0, -5, 0, 1, 0], [0, -4, -4, 1, 1, 0], [0, 4, -4, -1, 1, 0], [0, -2, -1, 2, 1, 0],
                  [0, 2, -1, -2, 1, 0], [0, 4, 0, -5, 0, 1]]),
            G=T([[1 / 4, 0, 0], [-1 / 6, -1 / 6, -1 / 6], [-1 / 6, 1 / 6, -1 / 6], [1 / 24, 1 / 12, 1 / 6],
                 [1 / 24, -1 / 12, 1 / 6], [0, 0, 1]]),
            AT=T([[1, 1, 1, 1, 1, 0], [0, 1, -1, 2, -2, 0], [0, 1, 1, 4, 4, 0], [0, 1, -1, 8, -8, 1]])),
    6: dict(BT=T([[1, 0, -21 / 4, 0, 21 / 4, 0, -1, 0], [0, 1, 1, -17 / 4, -17 / 4, 1, 1, 0],
                  [0, -1, 1, 17 / 4, -17 / 4, -1, 1, 0], [0, 1 / 2, 1 / 4, -5 / 2, -5 / 4, 2, 1, 0],
                  [0, -1 / 2, 1 / 4, 5 / 2, -5 / 4, -2, 1, 0], [0, 2, 4, -5 / 2, -5, 1 / 2, 1, 0],
                  [0, -2, 4, 5 / 2, -5, -1 / 2, 1, 0], [0, -1, 0, 21 / 4, 0, -21 / 4, 0, 1]]),
            G=T([[1, 0, 0], [-2 / 9, -2 / 9, -2 / 9], [-2 / 9, 2 / 9, -2 / 9], [1 / 90, 1 / 45, 2 / 45],
                 [1 / 90, -1 / 45, 2 / 45], [32 / 45, 16 / 45, 8 / 45], [32 / 45, -16 / 45, 8 / 45], [0, 0, 1]]),
            AT=T([[1, 1, 1, 1, 1, 1, 1, 0], [0, 1, -1, 2, -2, 1 / 2, -1 / 2, 0], [0, 1, 1, 4, 4, 1 / 4, 1 / 4, 0],
                  [0, 1, -1, 8, -8, 1 / 8, -1 / 8, 0], [0, 1, 1, 16, 16, 1 / 16, 1 / 16, 0],
                  [0, 1, -1, 32, -32, 1 / 32, -1 / 32, 1]])),
}


def onnx_initializers(path):
    """name -> float32 array of an ONNX file's initializers (a minimal protobuf reader: no onnx module needed)."""
    def varint(b, i):
        value = shift = 0
        while True:
            byte = b[i]
            i += 1
            value |= (byte & 0x7F) << shift
            shift += 7
            if byte < 0x80:
                return value, i

    def fields(b):
        i = 0
        while i < len(b):
            key, i = varint(b, i)
            wire = key & 7
            if wire == 0:
                value, i = varint(b, i)
            elif wire == 2:
                n, i = varint(b, i)
                value, i = b[i:i + n], i + n
            else:
                n = 4 if wire == 5 else 8
                value, i = b[i:i + n], i + n
            yield key >> 3, wire, value

    tensors = {}
    for field, _, graph in fields(open(path, "rb").read()):
        if field != 7:  # ModelProto.graph
            continue
        for g_field, _, tensor in fields(graph):
            if g_field != 5:  # GraphProto.initializer
                continue
            dims, name, data = [], "", b""
            for t_field, wire, value in fields(tensor):
                if t_field == 1 and wire == 0:
                    dims.append(value)
                elif t_field == 1:  # packed dims
                    i = 0
                    while i < len(value):
                        d, i = varint(value, i)
                        dims.append(d)
                elif t_field == 8:
                    name = value.decode()
                elif t_field in (4, 9):  # float_data (packed) or raw_data
                    data = value
            tensors[name] = np.frombuffer(data, np.float32).reshape(dims)
    return tensors


def stored(x, half):
    return x.half().double() if half else x.float().double()


def winograd_conv(x, w, b, variant):
    m = variant["m"]
    BT, G, AT = (MATRICES[m][k] for k in ("BT", "G", "AT"))
    channels, height, width = x.shape
    ty, tx = -(-height // m), -(-width // m)
    padded = torch.zeros(channels, ty * m + 2, tx * m + 2, dtype=torch.float64)
    padded[:, 1:height + 1, 1:width + 1] = x
    d = padded.unfold(1, m + 2, m).unfold(2, m + 2, m)  # channel, tile row, tile column, window
    V = stored(torch.einsum("ai,ctxij,bj->ctxab", BT, d, BT), variant["V"])
    U = stored(torch.einsum("ai,ocij,bj->ocab", G, w, G), variant["U"])
    M = stored(torch.einsum("ctxab,ocab->otxab", V, U), variant["M"])
    Y = torch.einsum("ai,otxij,bj->otxab", AT, M, AT).permute(0, 1, 3, 2, 4).reshape(w.shape[0], ty * m, tx * m)
    return Y[:, :height, :width] + b[:, None, None]


def superpoint(image, weights, variant):
    # The stem's output is stored (and rounded) where conv1a runs as its own layer, not inside a Winograd
    # input transform.
    stem_stored = not variant["m"]

    def conv(x, name, relu=True):
        half_weights = variant.get("weights", False) and name not in variant.get("fp32_weights", ())
        w, b = stored(weights[name + ".weight"], half_weights), weights[name + ".bias"]
        if variant["m"] and w.shape[2] == 3 and name != "conv1a":
            y = winograd_conv(x, w, b, variant)
        else:
            y = F.conv2d(x[None], w, b, padding=w.shape[2] // 2)[0]
        rounded = variant["activations"] and (name != "conv1a" or stem_stored)
        return stored(F.relu(y), rounded) if relu else y

    x = stored(image, variant.get("input", False))[None]
    for i, name in enumerate(["conv1a", "conv1b", "conv2a", "conv2b", "conv3a", "conv3b", "conv4a", "conv4b"]):
        x = conv(x, name)
        if i in (1, 3, 5):
            x = F.max_pool2d(x[None], 2, 2)[0]
    scores = F.softmax(conv(conv(x, "convPa"), "convPb", relu=False), 0)[:-1]
    _, h, w = scores.shape
    scores = scores.permute(1, 2, 0).reshape(h, w, 8, 8).permute(0, 2, 1, 3).reshape(h * 8, w * 8)
    return scores, F.normalize(conv(conv(x, "convDa"), "convDb", relu=False), dim=0)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser()
    parser.add_argument("--data", default=os.environ.get("VKVO_DATA", os.path.join(here, "..", "..", "shared")))
    parser.add_argument("cases", nargs="*", default=["euroc_0000_crop", "euroc_0005_crop"])
    args = parser.parse_args()
    torch.set_num_threads(2)
    weights = {name: torch.from_numpy(a.copy()).double()
               for name, a in onnx_initializers(os.path.join(args.data, "models", "superpoint_v1.onnx")).items()}
    fp32 = dict(m=0, V=False, U=False, M=False, activations=False)  # m = 0: direct convolutions
    half_activations = dict(fp32, activations=True)
    variants = [("direct, fp32", fp32), ("direct, 16-bit activations (fp16s)", half_activations),
                ("direct, + 16-bit weights", dict(half_activations, weights=True)),
                ("direct, + 16-bit weights but conv1a's", dict(half_activations, weights=True, fp32_weights={"conv1a"})),
                ("direct, + 16-bit weights but conv1a/1b's",
                 dict(half_activations, weights=True, fp32_weights={"conv1a", "conv1b"})),
                ("direct, + 16-bit input pixel / 255", dict(half_activations, input=True)),
                ("direct, + both (fp16s before 2026-12-03)", dict(half_activations, weights=True, input=True)),
                ("F(6x6), fp32", dict(fp32, m=6))]
    for m in (4, 6):
        variants += [(f"F({m}x{m}), 16-bit U", dict(fp32, m=m, U=True, activations=True)),
                     (f"F({m}x{m}), 16-bit V", dict(fp32, m=m, V=True, activations=True)),
                     (f"F({m}x{m}), 16-bit V, U, M", dict(fp32, m=m, V=True, U=True, M=True, activations=True))]
    print(f"{'case':16s} {'variant':42s} {'score max abs':>13s} {'worst desc cos':>14s}")
    for case in args.cases:
        folder = os.path.join(args.data, "golden", "superpoint", case)
        pixels = np.asarray(Image.open(os.path.join(folder, "image.png")).convert("L"), np.float64)
        image = torch.from_numpy(pixels / 255)
        ref_scores = torch.from_numpy(np.load(os.path.join(folder, "dense_scores.npy"))).double()
        ref_desc = torch.from_numpy(np.load(os.path.join(folder, "dense_descriptors.npy"))).double()
        for label, variant in variants:
            scores, desc = superpoint(image, weights, variant)
            error = (scores - ref_scores).abs().max().item()
            cosine = (desc * ref_desc).sum(0).min().item()
            print(f"{case:16s} {label:42s} {error:13.2e} {cosine:14.5f}", flush=True)


if __name__ == "__main__":
    main()
