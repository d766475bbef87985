#!/usr/bin/env python3
"""Fraction of triangles whose geometric normal agrees with their vertex normals (ASCII PLY with nx ny nz).
A mesh whose winding was not flipped under a mirroring transform scores near 0 instead of near 1."""
import sys
lines = open(sys.argv[1]).read().split("\n"); i = 0; props = []; nv = nf = 0; cur = None
while lines[i].strip() != "end_header":
    w = lines[i].split()
    if w[:1] == ["element"]: cur = w[1]; nv = int(w[2]) if cur == "vertex" else nv; nf = int(w[2]) if cur == "face" else nf
    if w[:1] == ["property"] and cur == "vertex": props.append(w[-1])
    i += 1
i += 1; V = [list(map(float, lines[i + k].split())) for k in range(nv)]; i += nv
px, nx = props.index("x"), props.index("nx"); agree = 0
for k in range(nf):
    a, b, c = [V[int(t)] for t in lines[i + k].split()[1:4]]
    e1 = [b[px + j] - a[px + j] for j in range(3)]; e2 = [c[px + j] - a[px + j] for j in range(3)]
    n = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]]
    vn = [a[nx + j] + b[nx + j] + c[nx + j] for j in range(3)]
    agree += sum(x * y for x, y in zip(n, vn)) > 0
print("%.4f" % (agree / max(nf, 1)))
