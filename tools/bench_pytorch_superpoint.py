#!/usr/bin/env python3
"""PyTorch CPU peer for `vkvo bench --superpoint`: SuperPoint's network (shared encoder 64-64-128-128 with three
2x2 max-pools, detector head 256 -> 65 with softmax, descriptor head 256 -> 256 with L2 normalisation) as in the
official module, with random weights (timing only), at 640x480 and 752x480. The post-processing (NMS, top-k,
descriptor sampling) is left out, which flatters PyTorch slightly: vkvo's figure includes it.

    /usr/bin/python3 tools/bench_pytorch_superpoint.py [--repeat 5] [--threads 2]
Prints the median seconds per size.
Each inference allocates its activations afresh; where page faults are costly (some VMs) that, not the
arithmetic, sets the time. To time PyTorch at its best, run it with an allocator that keeps its memory:
    LD_PRELOAD=/usr/lib/x86_64-linux-gnu/libjemalloc.so.2 MALLOC_CONF=retain:true,dirty_decay_ms:-1,muzzy_decay_ms:-1
(package libjemalloc2; docs/performance.md has both figures).
"""
import argparse
import statistics
import time

import torch
from torch import nn
from torch.nn import functional as F


class SuperPointNet(nn.Module):
    def __init__(self):
        super().__init__()
        widths = [(1, 64), (64, 64), (64, 64), (64, 64), (64, 128), (128, 128), (128, 128), (128, 128)]
        self.encoder = nn.ModuleList(nn.Conv2d(i, o, 3, padding=1) for i, o in widths)
        self.conv_pa, self.conv_pb = nn.Conv2d(128, 256, 3, padding=1), nn.Conv2d(256, 65, 1)
        self.conv_da, self.conv_db = nn.Conv2d(128, 256, 3, padding=1), nn.Conv2d(256, 256, 1)

    def forward(self, image):
        x = image
        for i, conv in enumerate(self.encoder):
            x = F.relu(conv(x))
            if i in (1, 3, 5):
                x = F.max_pool2d(x, 2, 2)
        scores = F.softmax(self.conv_pb(F.relu(self.conv_pa(x))), dim=1)[:, :-1]
        n, _, h, w = scores.shape
        scores = scores.permute(0, 2, 3, 1).reshape(n, h, w, 8, 8).permute(0, 1, 3, 2, 4).reshape(n, h * 8, w * 8)
        descriptors = F.normalize(self.conv_db(F.relu(self.conv_da(x))), p=2, dim=1)
        return scores, descriptors


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--threads", type=int, default=2)
    args = parser.parse_args()
    torch.set_num_threads(args.threads)
    torch.manual_seed(0)
    net = SuperPointNet().eval()
    print(f"PyTorch {torch.__version__}, {args.threads} threads")
    with torch.no_grad():
        for width, height in ((640, 480), (752, 480)):
            image = torch.rand(1, 1, height, width)
            net(image)  # warm-up
            times = []
            for _ in range(args.repeat):
                start = time.perf_counter()
                net(image)
                times.append(time.perf_counter() - start)
            print(f"{width}x{height}: median {statistics.median(times):.3f} s over {args.repeat} runs")


if __name__ == "__main__":
    main()
