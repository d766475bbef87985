#!/usr/bin/env python3
"""Compares two ASCII PLYs written by `lodforge convert --encoding ascii`: the set of triangles as
position triples (rotation-invariant, winding kept), and per-vertex attributes matched by position.
Prints the largest position, normal, colour and uv differences. Usage: compare_geometry.py A.ply B.ply"""
import sys

def load(path):
    lines = open(path).read().split("\n"); i = 0; props = []; nv = nf = 0; cur = None
    while lines[i].strip() != "end_header":
        w = lines[i].split()
        if w[:1] == ["element"]:
            cur = w[1]
            if cur == "vertex": nv = int(w[2])
            if cur == "face": nf = int(w[2])
        if w[:1] == ["property"] and cur == "vertex": props.append(w[-1])
        i += 1
    i += 1; V = [list(map(float, lines[i + k].split())) for k in range(nv)]; i += nv
    F = [list(map(int, lines[i + k].split()))[1:] for k in range(nf)]
    return props, V, F

def tri_key(V, f, q):
    pts = [tuple(round(V[v][c] / q) for c in range(3)) for v in f]
    k = min(range(3), key=lambda r: pts[r]); return tuple(pts[k:] + pts[:k])

pa, Va, Fa = load(sys.argv[1]); pb, Vb, Fb = load(sys.argv[2])
q = float(sys.argv[3]) if len(sys.argv) > 3 else 1e-4
ta = sorted(tri_key(Va, f, q) for f in Fa); tb = sorted(tri_key(Vb, f, q) for f in Fb)
same = sum(1 for x, y in zip(ta, tb) if x == y)
print("triangles %d vs %d, identical (quantum %g): %d" % (len(ta), len(tb), q, len(set(ta) & set(tb))))
def attrs(props, V, names):
    idx = [props.index(n) for n in names if n in props]
    return {tuple(round(v[c] / q) for c in range(3)): [v[i] for i in idx] for v in V} if len(idx) == len(names) else None
for names in (["nx", "ny", "nz"], ["red", "green", "blue", "alpha"], ["u", "v"]):
    A, B = attrs(pa, Va, names), attrs(pb, Vb, names)
    if A is None or B is None: print(names[0], "present:", A is not None, B is not None); continue
    d = max((max(abs(x - y) for x, y in zip(A[k], B[k])) for k in A if k in B), default=None)
    print(names[0], "max diff", d)
