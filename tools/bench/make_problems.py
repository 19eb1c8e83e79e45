#!/usr/bin/env python3
"""More problems drawn as the benchmark's local problems are (../shared/data/README.md).

The shared problem files hold 50 problems per set: one failure moves the success rate by 2 %, too
coarse to tell whether a change costs robustness. This writes N problems in the same format,
drawn from the same distribution: a rotation of uniform random magnitude in
[--min-rotation (default 0), --max-rotation] degrees about a uniformly random axis through the source's centroid, then a translation of uniform
random magnitude in [0, --max-translation] in a uniformly random direction.

  tools/bench/make_problems.py ../shared/data/benchmark lidar/source.ply lidar/target.ply \\
      --max-translation 1 --count 300 --seed 1 --first-id 5000 > /tmp/lidar_300.txt

The file names its clouds relative to the benchmark folder, as the shared files do, so ppcr_bench
reads it with --data-root (or from a copy of the file in that folder). Standard library only; reads
binary little-endian and ASCII PLY with float or double x, y, z.
"""
import argparse
import math
import random
import struct
import sys

PLY_TYPES = {"float": ("f", 4), "float32": ("f", 4), "double": ("d", 8), "float64": ("d", 8),
             "uchar": ("B", 1), "uint8": ("B", 1), "char": ("b", 1), "int8": ("b", 1),
             "ushort": ("H", 2), "uint16": ("H", 2), "short": ("h", 2), "int16": ("h", 2),
             "uint": ("I", 4), "uint32": ("I", 4), "int": ("i", 4), "int32": ("i", 4)}


def centroid(path):
    """Mean of the vertices' x, y, z of a PLY file (the first element must be 'vertex')."""
    with open(path, "rb") as f:
        if f.readline().strip() != b"ply":
            sys.exit(f"{path}: not a PLY file")
        fmt, count, props = None, 0, []
        in_vertex = False
        while True:
            line = f.readline()
            if not line:
                sys.exit(f"{path}: no end_header")
            words = line.decode("ascii", "replace").split()
            if not words:
                continue
            if words[0] == "format":
                fmt = words[1]
            elif words[0] == "element":
                in_vertex = words[1] == "vertex"
                if in_vertex:
                    count = int(words[2])
            elif words[0] == "property" and in_vertex:
                if words[1] == "list":
                    sys.exit(f"{path}: list property in the vertex element is not supported")
                if words[1] not in PLY_TYPES:
                    sys.exit(f"{path}: property type '{words[1]}' is not supported")
                props.append((words[2], words[1]))
            elif words[0] == "end_header":
                break
        names = [p[0] for p in props]
        if not all(a in names for a in "xyz") or count <= 0:
            sys.exit(f"{path}: needs a vertex element with x, y, z (found {names}, {count} vertices)")
        xyz = [names.index(a) for a in "xyz"]
        total = [0.0, 0.0, 0.0]
        if fmt == "binary_little_endian":
            record = struct.Struct("<" + "".join(PLY_TYPES[t][0] for _, t in props))
            data = f.read(record.size * count)
            if len(data) < record.size * count:
                sys.exit(f"{path}: {count} vertices announced, the file ends early")
            for v in record.iter_unpack(data):
                for a in range(3):
                    total[a] += v[xyz[a]]
        elif fmt == "ascii":
            for i in range(count):
                v = f.readline().split()
                if len(v) < len(props):
                    sys.exit(f"{path}: vertex {i} has {len(v)} values, expected {len(props)}")
                for a in range(3):
                    total[a] += float(v[xyz[a]])
        else:
            sys.exit(f"{path}: PLY format '{fmt}' is not supported")
        return [t / count for t in total]


def random_unit(rng):
    while True:
        v = [rng.gauss(0.0, 1.0) for _ in range(3)]
        n = math.sqrt(sum(x * x for x in v))
        if n > 1e-9:
            return [x / n for x in v]


def rotation(axis, angle):
    """Rodrigues: the 3x3 rotation by angle (radians) about the unit axis."""
    x, y, z = axis
    c, s = math.cos(angle), math.sin(angle)
    C = 1.0 - c
    return [[c + x * x * C, x * y * C - z * s, x * z * C + y * s],
            [y * x * C + z * s, c + y * y * C, y * z * C - x * s],
            [z * x * C - y * s, z * y * C + x * s, c + z * z * C]]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("benchmark_dir", help="folder the cloud paths are relative to")
    ap.add_argument("source", help="source cloud (PLY), relative to benchmark_dir")
    ap.add_argument("target", help="target cloud, relative to benchmark_dir")
    ap.add_argument("--count", type=int, default=300, help="problems to write (default 300)")
    ap.add_argument("--min-rotation", type=float, default=0.0, help="degrees (default 0)")
    ap.add_argument("--max-rotation", type=float, default=30.0, help="degrees (default 30)")
    ap.add_argument("--max-translation", type=float, required=True,
                    help="cloud units (the benchmark: 0.02 bunny, 1 lidar)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--first-id", type=int, default=5000)
    ap.add_argument("--overlap", default="0", help="the overlap column, copied (default 0)")
    a = ap.parse_args()
    if a.count < 1 or not (0.0 <= a.min_rotation <= a.max_rotation <= 180.0) or \
            not (a.max_translation >= 0.0):
        sys.exit(f"need --count >= 1 (got {a.count}), 0 <= --min-rotation ({a.min_rotation}) "
                 f"<= --max-rotation <= 180 "
                 f"(got {a.max_rotation}), --max-translation >= 0 (got {a.max_translation})")
    c = centroid(f"{a.benchmark_dir}/{a.source}")
    rng = random.Random(a.seed)
    print("id source target overlap t1 t2 t3 t4 t5 t6 t7 t8 t9 t10 t11 t12")
    for i in range(a.count):
        R = rotation(random_unit(rng), math.radians(rng.uniform(a.min_rotation, a.max_rotation)))
        d = random_unit(rng)
        m = rng.uniform(0.0, a.max_translation)
        # x -> R (x - c) + c + t: rotation about the centroid, then the translation.
        t = [c[r] - sum(R[r][j] * c[j] for j in range(3)) + m * d[r] for r in range(3)]
        rows = [R[r] + [t[r]] for r in range(3)]
        print(a.first_id + i, a.source, a.target, a.overlap,
              " ".join(repr(v) for row in rows for v in row))


if __name__ == "__main__":
    main()
