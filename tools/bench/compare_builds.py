#!/usr/bin/env python3
"""Compares ppcr_bench builds on the benchmark sets, robustly to a noisy machine.

    tools/bench/compare_builds.py [--limit N] [--reps R] [--sets "bunny lidar"] BENCH [BENCH ...]
        [-- extra ppcr_bench options]

Runs every build R times on the first N problems of each set (interleaved: build 1, build 2,
..., then the next repetition), one thread, with the protocol of the docs' reference figures
(tools/bench/protocol.txt).
Per build it prints the sum over problems of each problem's minimum time over the repetitions
(the minimum drops the runs another process slowed down), the median of those minima, and the
median and 0.95 quantile of the error and the mean iterations of the last repetition (errors
are deterministic). Standard library only.
"""
import argparse
import csv
import os
import statistics
import subprocess
import sys
import tempfile

def read_protocol(path):
    """tools/bench/protocol.txt: {set: ppcr_bench options}, the one definition of the protocol."""
    protocol = {}
    with open(path) as f:
        for line in f:
            line = line.strip()
            if line and not line.startswith('#'):
                name, _, options = line.partition(' ')
                protocol.setdefault(name, options)  # the first line of a set, as grep -m1
    return protocol


def quantile(values, q):
    """numpy's linear interpolation, as ppcr_bench's summary."""
    v = sorted(values)
    position = q * (len(v) - 1)
    lo = int(position)
    hi = min(lo + 1, len(v) - 1)
    return v[lo] + (position - lo) * (v[hi] - v[lo])


def main():
    argv = sys.argv[1:]
    extra = []
    if '--' in argv:
        extra = argv[argv.index('--') + 1:]
        argv = argv[:argv.index('--')]
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('benches', nargs='+', help='ppcr_bench executables')
    parser.add_argument('--limit', type=int, default=20, help='first N problems (default 20)')
    parser.add_argument('--reps', type=int, default=3, help='repetitions (default 3)')
    parser.add_argument('--sets', default='bunny lidar', help='sets (default "bunny lidar")')
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    parser.add_argument('--data', default=os.path.join(root, '..', 'shared', 'data', 'benchmark'),
                        help='folder of the problem files (default ../shared/data/benchmark)')
    args = parser.parse_args(argv)
    protocol_file = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'protocol.txt')
    protocol = read_protocol(protocol_file)
    for s in args.sets.split():
        if s not in protocol:
            sys.exit(f"compare_builds.py: no protocol for set '{s}' in {protocol_file}")
    with tempfile.TemporaryDirectory() as tmp:
        for s in args.sets.split():
            times = {b: {} for b in args.benches}
            errors = {}
            for _ in range(args.reps):
                for i, b in enumerate(args.benches):
                    out = os.path.join(tmp, f'{i}.csv')
                    cmd = [b, os.path.join(args.data, f'{s}_local.txt'), *protocol[s].split(),
                           '--threads', '1', '--quiet', '--limit', str(args.limit), '--out', out,
                           *extra]
                    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
                    with open(out) as f:
                        rows = list(csv.DictReader(f))
                    for row in rows:
                        times[b].setdefault(row['id'], []).append(float(row['time_ms']))
                    e = [float(row['error']) for row in rows]
                    errors[b] = (quantile(e, 0.5), quantile(e, 0.95),
                                 statistics.mean(float(row['iterations']) for row in rows))
            for b in args.benches:
                minima = [min(v) for v in times[b].values()]
                print(f'{s} {b}: sum of minima {sum(minima):.1f} ms, median of minima '
                      f'{statistics.median(minima):.1f} ms, error median {errors[b][0]:.7g} '
                      f'q0.95 {errors[b][1]:.7g}, iterations {errors[b][2]:.2f}')


if __name__ == '__main__':
    main()
