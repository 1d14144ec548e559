#!/usr/bin/env python3
"""Packing figures of a set of elliptical samples, measured independently of the sampler.

    packing.py field NAME OUT.npy [--side N] [--count N]   write a test metric as .npy
    packing.py eval SAMPLES.csv FIELD.npy [--nn-only]       coverage, overlap, N, nn distances
    packing.py bamg-inputs FIELD.npy DIR                    BAMG background mesh + metric
    packing.py bamg-samples MESH FIELD.npy OUT.csv          BAMG's vertices as samples

Conventions (the project's, restated here so this file imports nothing from it): a sample
is a row x,y,m11,m12,m22 (pixels); its ellipse is {p + m u : |u| = 1}, so m's eigenvalues are
the semi-axes. A field .npy is (H, W, 3) of (m11, m12, m22) at pixel centres.

- coverage: share of the domain [0,W]x[0,H] inside at least one ellipse, overlap: inside two
  or more; both by rasterising every ellipse on a grid of SS x SS points per pixel;
- ideal count: the integral of 1 / (2 sqrt(3) det m) over the domain (hexagonal packing);
- nearest-neighbour distance (paper section 6, eq. 4): d = |y| / (r_a(y) + r_b(y)) with
  r(u) = 1 / |m^-1 u|, the minimum over all other samples. Exact: every sample is compared
  with all samples within a Euclidean radius that provably holds every d <= 2 (brute force
  over the rest when none is found).
"""
import math
import sys

import numpy as np

SS = 3  # raster points per pixel side for coverage and overlap


def metric(angle, long_axis, short_axis):
    c, s = np.cos(angle), np.sin(angle)
    m11 = long_axis * c * c + short_axis * s * s
    m22 = long_axis * s * s + short_axis * c * c
    m12 = (long_axis - short_axis) * c * s
    return np.stack([m11, m12, m22], axis=-1)


def make_field(name, side, count):
    """Test metrics. `rotating`: 4:1 ellipses whose axes turn by pi across the unit square
    (the angle grows along x and along y), sized for `count` samples. `constant2`: a constant
    2:1 metric, semi-axes 3 and 1.5 px. `sizes`: isotropic, size growing 3x across x."""
    y, x = np.mgrid[0:side, 0:side].astype(np.float64) + 0.5
    u, v = x / side, y / side
    if name == "rotating":
        area_each = side * side / count / (2 * math.sqrt(3))  # a * b
        b = math.sqrt(area_each / 4.0)
        return metric(math.pi * (0.6 * u + 0.4 * v), 4 * b + 0 * u, b + 0 * u)
    if name == "constant2":
        return metric(0 * u, 3.0 + 0 * u, 1.5 + 0 * u)
    if name == "sizes":
        scale = 1.0 + 2.0 * u
        b = math.sqrt(side * side / count / (2 * math.sqrt(3)) / 2.3)
        return metric(0 * u, b * scale, b * scale)
    raise SystemExit(f"unknown field {name}")


def read_samples(path):
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return data[:, :2], data[:, 2:5]


def inverses(m):
    det = m[:, 0] * m[:, 2] - m[:, 1] ** 2
    return np.stack([m[:, 2] / det, -m[:, 1] / det, m[:, 0] / det], axis=1)


def coverage(pos, m, width, height):
    count = np.zeros((height * SS, width * SS), dtype=np.uint8)
    inv = inverses(m)
    for (px, py), (a, b, c), (m11, m12, m22) in zip(pos, inv, m):
        # half extents of the ellipse's bounding box
        hx = math.sqrt(m11 * m11 + m12 * m12)
        hy = math.sqrt(m12 * m12 + m22 * m22)
        x0 = max(int(math.floor((px - hx) * SS)), 0)
        x1 = min(int(math.ceil((px + hx) * SS)) + 1, width * SS)
        y0 = max(int(math.floor((py - hy) * SS)), 0)
        y1 = min(int(math.ceil((py + hy) * SS)) + 1, height * SS)
        if x0 >= x1 or y0 >= y1:
            continue
        xs = (np.arange(x0, x1) + 0.5) / SS - px
        ys = (np.arange(y0, y1) + 0.5) / SS - py
        dx, dy = np.meshgrid(xs, ys)
        ux = a * dx + b * dy
        uy = b * dx + c * dy
        inside = ux * ux + uy * uy <= 1.0
        block = count[y0:y1, x0:x1]
        block += inside.astype(np.uint8) * (block < 250)
    total = count.size
    return np.count_nonzero(count >= 1) / total, np.count_nonzero(count >= 2) / total


def radius_along(inv, ux, uy):
    """1 / |m^-1 u| for unit u, inv rows (a, b, c) of the symmetric inverse."""
    vx = inv[..., 0] * ux + inv[..., 1] * uy
    vy = inv[..., 1] * ux + inv[..., 2] * uy
    return 1.0 / np.sqrt(vx * vx + vy * vy)


def nearest_distances(pos, m):
    from scipy.spatial import cKDTree

    n = len(pos)
    inv = inverses(m)
    long_axis = 0.5 * (m[:, 0] + m[:, 2]) + np.sqrt(0.25 * (m[:, 0] - m[:, 2]) ** 2 + m[:, 1] ** 2)
    # d <= 2 needs |y| <= 2 (r_a + r_b) <= 2 (a_i + a_max)
    radius = 2.0 * (long_axis + long_axis.max())
    tree = cKDTree(pos)
    nn = np.full(n, np.inf)
    for i in range(n):
        js = np.array(tree.query_ball_point(pos[i], radius[i]), dtype=np.int64)
        js = js[js != i]
        if len(js) == 0:
            js = np.delete(np.arange(n), i)
        y = pos[js] - pos[i]
        dist = np.hypot(y[:, 0], y[:, 1])
        ux, uy = y[:, 0] / dist, y[:, 1] / dist
        d = dist / (radius_along(inv[i], ux, uy) + radius_along(inv[js], ux, uy))
        nn[i] = d.min()
    return nn


def ideal_count(field):
    det = field[..., 0] * field[..., 2] - field[..., 1] ** 2
    return float(np.sum(1.0 / (2.0 * math.sqrt(3.0) * det)))


def evaluate(samples, field_path, nn_only):
    pos, m = read_samples(samples)
    field = np.load(field_path)
    height, width = field.shape[:2]
    ideal = ideal_count(field)
    out = {"samples": len(pos), "ideal": round(ideal), "n_ratio": len(pos) / ideal}
    if not nn_only:
        cov, over = coverage(pos, m, width, height)
        out["coverage"], out["overlap"] = cov, over
    nn = np.sort(nearest_distances(pos, m))
    out["nn_min"], out["nn_p5"] = nn[0], nn[int(0.05 * (len(nn) - 1))]
    out["nn_median"], out["nn_mean"] = float(np.median(nn)), float(nn.mean())
    print(" ".join(f"{k} {v:.4f}" if isinstance(v, float) else f"{k} {v}" for k, v in out.items()))


def bamg_inputs(field_path, out_dir):
    """A background mesh of the unit square scaled to pixels (a grid of two triangles per
    cell) and BAMG's metric at its vertices: M = (2 m)^-2, so that BAMG's unit edge is the
    distance of two touching ellipses."""
    field = np.load(field_path)
    height, width = field.shape[:2]
    nx = ny = 65
    xs = np.linspace(0, width, nx)
    ys = np.linspace(0, height, ny)
    with open(f"{out_dir}/bg.mesh", "w") as f:
        f.write("MeshVersionFormatted 0\nDimension 2\n")
        f.write(f"Vertices {nx * ny}\n")
        for y in ys:
            for x in xs:
                f.write(f"{x} {y} 0\n")
        f.write(f"Triangles {2 * (nx - 1) * (ny - 1)}\n")
        for j in range(ny - 1):
            for i in range(nx - 1):
                a = j * nx + i + 1
                f.write(f"{a} {a + 1} {a + nx + 1} 0\n{a} {a + nx + 1} {a + nx} 0\n")
        edges = []
        for i in range(nx - 1):
            edges.append((i + 1, i + 2, 1))
            edges.append(((ny - 1) * nx + i + 1, (ny - 1) * nx + i + 2, 3))
        for j in range(ny - 1):
            edges.append((j * nx + 1, (j + 1) * nx + 1, 4))
            edges.append((j * nx + nx, (j + 1) * nx + nx, 2))
        f.write(f"Edges {len(edges)}\n")
        for a, b, r in edges:
            f.write(f"{a} {b} {r}\n")
        f.write("End\n")
    with open(f"{out_dir}/bg.mtr", "w") as f:
        f.write(f"{nx * ny} 3\n")
        for y in ys:
            for x in xs:
                i = min(int(x), width - 1)
                j = min(int(y), height - 1)
                m11, m12, m22 = field[j, i]
                big = np.array([[m11, m12], [m12, m22]]) * 2.0
                inv = np.linalg.inv(big)
                bm = inv @ inv
                f.write(f"{bm[0, 0]} {bm[0, 1]} {bm[1, 1]}\n")


def bamg_samples(mesh_path, field_path, out_csv):
    field = np.load(field_path)
    height, width = field.shape[:2]
    words = open(mesh_path).read().split()
    at = words.index("Vertices")
    n = int(words[at + 1])
    vals = np.array(words[at + 2 : at + 2 + 3 * n], dtype=np.float64).reshape(n, 3)
    pos = vals[:, :2]
    i = np.clip(pos[:, 0].astype(int), 0, width - 1)
    j = np.clip(pos[:, 1].astype(int), 0, height - 1)
    m = field[j, i]
    with open(out_csv, "w") as f:
        f.write("x,y,m11,m12,m22\n")
        for (x, y), (a, b, c) in zip(pos, m):
            f.write(f"{x},{y},{a},{b},{c}\n")


def main(argv):
    if len(argv) < 2:
        raise SystemExit(__doc__)
    cmd = argv[1]
    if cmd == "field":
        side, count = 1024, 11000
        args = argv[2:]
        if "--side" in args:
            side = int(args[args.index("--side") + 1])
        if "--count" in args:
            count = int(args[args.index("--count") + 1])
        np.save(args[1], make_field(args[0], side, count).astype(np.float32))
    elif cmd == "eval":
        evaluate(argv[2], argv[3], "--nn-only" in argv)
    elif cmd == "bamg-inputs":
        bamg_inputs(argv[2], argv[3])
    elif cmd == "bamg-samples":
        bamg_samples(argv[2], argv[3], argv[4])
    else:
        raise SystemExit(__doc__)


if __name__ == "__main__":
    main(sys.argv)
