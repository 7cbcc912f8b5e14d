#!/usr/bin/env python3
"""PyTorch CPU peer for `vkvo bench --superglue`: SuperGlue's architecture (keypoint encoder 32-64-128-256,
18 self/cross attentional layers with 4 heads, final projection, 100 log-space Sinkhorn iterations, mutual-max
extraction) written after the official module, with random weights (timing only), at N = M = 200, 400, 1000.

    LP_NUM_THREADS=2 python3 tools/bench_pytorch_superglue.py [--repeat 5] [--threads 2]
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


def mlp(channels):
    layers = []
    for i in range(1, len(channels)):
        layers.append(nn.Conv1d(channels[i - 1], channels[i], kernel_size=1, bias=True))
        if i < len(channels) - 1:
            layers.append(nn.BatchNorm1d(channels[i]))
            layers.append(nn.ReLU())
    return nn.Sequential(*layers)


class Attention(nn.Module):
    def __init__(self, heads, dim):
        super().__init__()
        self.heads, self.head_dim = heads, dim // heads
        self.merge = nn.Conv1d(dim, dim, kernel_size=1)
        self.proj = nn.ModuleList([nn.Conv1d(dim, dim, kernel_size=1) for _ in range(3)])

    def forward(self, query, key, value):
        b = query.size(0)
        query, key, value = [l(x).view(b, self.head_dim, self.heads, -1)
                             for l, x in zip(self.proj, (query, key, value))]
        scores = torch.einsum('bdhn,bdhm->bhnm', query, key) / self.head_dim ** .5
        prob = torch.nn.functional.softmax(scores, dim=-1)
        x = torch.einsum('bhnm,bdhm->bdhn', prob, value)
        return self.merge(x.contiguous().view(b, self.head_dim * self.heads, -1))


class Propagation(nn.Module):
    def __init__(self, dim, heads):
        super().__init__()
        self.attn = Attention(heads, dim)
        self.mlp = mlp([dim * 2, dim * 2, dim])

    def forward(self, x, source):
        return self.mlp(torch.cat([x, self.attn(x, source, source)], dim=1))


def log_optimal_transport(scores, alpha, iters):
    b, m, n = scores.shape
    one = scores.new_tensor(1)
    ms, ns = (m * one).to(scores), (n * one).to(scores)
    couplings = torch.cat([torch.cat([scores, alpha.expand(b, m, 1)], -1),
                           torch.cat([alpha.expand(b, 1, n), alpha.expand(b, 1, 1)], -1)], 1)
    norm = -(ms + ns).log()
    log_mu = torch.cat([norm.expand(m), ns.log()[None] + norm])[None]
    log_nu = torch.cat([norm.expand(n), ms.log()[None] + norm])[None]
    u, v = torch.zeros_like(log_mu), torch.zeros_like(log_nu)
    for _ in range(iters):
        u = log_mu - torch.logsumexp(couplings + v.unsqueeze(1), dim=2)
        v = log_nu - torch.logsumexp(couplings + u.unsqueeze(2), dim=1)
    return couplings + u.unsqueeze(2) + v.unsqueeze(1) - norm


class SuperGlue(nn.Module):
    def __init__(self, dim=256, layers=18):
        super().__init__()
        self.kenc = mlp([3, 32, 64, 128, 256, dim])
        self.gnn = nn.ModuleList([Propagation(dim, 4) for _ in range(layers)])
        self.names = ['self', 'cross'] * (layers // 2)
        self.final_proj = nn.Conv1d(dim, dim, kernel_size=1)
        self.bin_score = nn.Parameter(torch.tensor(1.))

    def forward(self, kpts0, scores0, desc0, kpts1, scores1, desc1):
        desc0 = desc0 + self.kenc(torch.cat([kpts0.transpose(1, 2), scores0.unsqueeze(1)], dim=1))
        desc1 = desc1 + self.kenc(torch.cat([kpts1.transpose(1, 2), scores1.unsqueeze(1)], dim=1))
        for layer, name in zip(self.gnn, self.names):
            src0, src1 = (desc1, desc0) if name == 'cross' else (desc0, desc1)
            delta0, delta1 = layer(desc0, src0), layer(desc1, src1)
            desc0, desc1 = desc0 + delta0, desc1 + delta1
        mdesc0, mdesc1 = self.final_proj(desc0), self.final_proj(desc1)
        scores = torch.einsum('bdn,bdm->bnm', mdesc0, mdesc1) / mdesc0.shape[1] ** .5
        scores = log_optimal_transport(scores, self.bin_score, 100)
        max0, max1 = scores[:, :-1, :-1].max(2), scores[:, :-1, :-1].max(1)
        indices0, indices1 = max0.indices, max1.indices
        mutual0 = torch.arange(indices0.shape[1])[None] == indices1.gather(1, indices0)
        mscores0 = torch.where(mutual0, max0.values.exp(), scores.new_tensor(0))
        return torch.where(mutual0 & (mscores0 > 0.2), indices0, indices0.new_tensor(-1)), mscores0


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--repeat', type=int, default=5)
    parser.add_argument('--threads', type=int, default=2)
    parser.add_argument('--sizes', type=int, nargs='+', default=[200, 400, 1000])
    args = parser.parse_args()
    torch.set_num_threads(args.threads)
    torch.manual_seed(0)
    model = SuperGlue().eval()
    print(f'PyTorch {torch.__version__}, {torch.get_num_threads()} threads')
    for n in args.sizes:
        inputs = (torch.rand(1, n, 2) - 0.5, torch.rand(1, n), nn.functional.normalize(torch.randn(1, 256, n), dim=1))
        with torch.no_grad():
            model(*inputs, *inputs)
            times = []
            for _ in range(args.repeat):
                start = time.perf_counter()
                model(*inputs, *inputs)
                times.append(time.perf_counter() - start)
        print(f'N=M={n:5d}: median {statistics.median(times):.3f} s over {args.repeat} runs')


if __name__ == '__main__':
    main()
