#!/usr/bin/env python3
"""Runs every CLI command on every variant of gen_variants.py and checks the result (QA matrix).

Usage: run_matrix.py LODFORGE_BIN VARIANT_DIR [--only PREFIX] [--commands info,convert_ply,...]
Environment: GLTF_VALIDATOR=tests/gltf_validator/validate.js validates every .glb written;
FORMAT_DRIVER=build-asan/bin/format_driver runs the sanitizer driver on every variant first.
Checks: no signal, no hang (timeout), no sanitizer report; good input exits 0 with the expected counts
and attributes (outputs re-read with `info`); bad input exits 1 with `lodforge: error: <file>: ...` and
leaves no output behind. Prints one line per failure and a variant x command matrix.
"""
import json, os, shutil, subprocess, sys, tempfile

BIN, VDIR = sys.argv[1], sys.argv[2]
only = sys.argv[sys.argv.index("--only") + 1] if "--only" in sys.argv else ""
CMDS = ["info", "convert_ply", "convert_obj", "convert_glb", "simplify", "lod", "compare", "octree", "mcoctree", "strips", "pack"]
if "--commands" in sys.argv: CMDS = sys.argv[sys.argv.index("--commands") + 1].split(",")
TIMEOUT = 120
VALIDATOR = os.environ.get("GLTF_VALIDATOR")
manifest = [m for m in json.load(open(os.path.join(VDIR, "manifest.json"))) if m["name"].startswith(only)]
work = tempfile.mkdtemp(prefix="lf-matrix-")
preset = os.path.join(work, "preset.json")
json.dump({"version": 1, "levels": [{"ratio": 0.5}], "export": {"glb": True, "ply": True, "obj": True}}, open(preset, "w"))

def run(args):
    try:
        p = subprocess.run([BIN, "--quiet"] + args, capture_output=True, text=True, errors="replace", timeout=TIMEOUT)
        return p.returncode, p.stdout, p.stderr
    except subprocess.TimeoutExpired:
        return "HANG", "", ""

def info(path):
    rc, out, err = run(["info", "--json", path])
    if rc != 0: return None, err
    try: return json.loads(out), ""
    except Exception as e: return None, "bad json: %s" % e

failures = []; matrix = {}
def fail(v, c, msg):
    failures.append("%s / %s: %s" % (v["name"], c, msg.strip().replace("\n", " | ")[:400]))
    return "FAIL"

def sanitizer(err):
    return "AddressSanitizer" in err or "runtime error:" in err or "LeakSanitizer" in err

def expect_error(v):
    return v.get("error", False)

def check(v, c, rc, out, err, outputs, verify=None):
    if rc == "HANG": return fail(v, c, "timeout after %ds" % TIMEOUT)
    if sanitizer(err): return fail(v, c, "sanitizer: " + err[err.find("ERROR") if "ERROR" in err else 0:][:300])
    if isinstance(rc, int) and (rc < 0 or rc >= 128): return fail(v, c, "signal/crash rc=%d %s" % (rc, err[-300:]))
    if rc == 3: return fail(v, c, "internal error rc=3: " + err)
    if rc == 0:
        if expect_error(v): return fail(v, c, "accepted bad input (rc 0)")
        if verify:
            msg = verify()
            if msg: return fail(v, c, msg)
        return "ok"
    # error paths
    lines = [l for l in err.splitlines() if l.startswith("lodforge: error:")]
    if rc != 1: return fail(v, c, "rc=%s (expected 0 or 1): %s" % (rc, err[-300:]))
    if not lines: return fail(v, c, "no 'lodforge: error:' line: " + err[-300:])
    left = [o for o in outputs if os.path.exists(o) and (not os.path.isdir(o) or os.listdir(o))]
    if left: return fail(v, c, "output left after error: %s" % left)
    stray = [f for f in os.listdir(os.path.dirname(outputs[0])) if ".tmp" in f or f.startswith(".")] if outputs else []
    if stray: return fail(v, c, "temporary files left: %s" % stray)
    if not expect_error(v) and not v.get("error_or_empty") and not v.get("error_or_ok"):
        # a clear refusal is acceptable for some commands on good input (point clouds, non-PLY octree input)
        return "refused: " + lines[0][:160]
    if v["file"] not in lines[0] and os.path.basename(v["file"]) not in lines[0] and not any(o in lines[0] for o in outputs):
        return fail(v, c, "error does not name the input: " + lines[0])
    return "error"

def count_check(v, j, what, strict_vertices=True, one_uv_set=False):
    if v.get("real"): return ""
    probs = []
    if one_uv_set and j.get("triangles", 0) == 0 and v.get("pointcloud"): pass
    if "triangles" in v and j["triangles"] != v["triangles"]: probs.append("triangles %d != %d" % (j["triangles"], v["triangles"]))
    if strict_vertices and "vertices" in v and j["vertices"] != v["vertices"]: probs.append("vertices %d != %d" % (j["vertices"], v["vertices"]))
    for a in v.get("attributes", []):
        if one_uv_set and a == "texcoord1": continue  # PLY/OBJ hold one set (the one the texture samples)
        if a not in j["attributes"]: probs.append("attribute %s missing (has %s)" % (a, j["attributes"]))
    return (what + ": " + "; ".join(probs)) if probs else ""

# FORMAT_DRIVER: a sanitizer build's format_driver (tests/formats/format_driver.cpp), run on each variant.
DRIVER = os.environ.get("FORMAT_DRIVER")
if DRIVER:
    for v in manifest:
        try:
            p = subprocess.run([DRIVER, os.path.join(work, "driver"), v["file"]], capture_output=True, text=True,
                               errors="replace", timeout=TIMEOUT)
            if p.returncode != 0 or sanitizer(p.stderr):
                failures.append("%s / format_driver: rc=%d %s" % (v["name"], p.returncode, p.stderr[:400]))
        except subprocess.TimeoutExpired:
            failures.append("%s / format_driver: timeout" % v["name"])
    print("format_driver: %d variants, %d failures" % (len(manifest), len(failures)), flush=True)

orig_info = {}
for v in manifest:
    name, f = v["name"], v["file"]
    d = os.path.join(work, name); os.makedirs(d, exist_ok=True)
    row = matrix.setdefault(name, {})
    base_tris = None
    for c in CMDS:
        outs = []; verify = None
        if c == "info":
            rc, out, err = run(["info", "--json", f])
            def verify(out=out):
                try: j = json.loads(out)
                except Exception as e: return "bad json %s" % e
                row["_info"] = j
                msg = count_check(v, j, "info")
                if msg: return msg
                if v.get("textures") and len(j.get("textures", [])) + j.get("embedded_textures", 0) < v["textures"] and not v.get("embedded_textures"):
                    return "textures %s (expected %d)" % (j.get("textures"), v["textures"])
                if v.get("missing_textures") and len(j.get("missing_textures", [])) != v["missing_textures"]:
                    return "missing_textures %s" % j.get("missing_textures")
                if v.get("materials") and j["materials"] < v["materials"]: return "materials %d < %d" % (j["materials"], v["materials"])
                if v.get("orig") and v.get("same_geometry"):
                    oi = orig_info.get(v["orig"]) or info(v["orig"])[0]; orig_info[v["orig"]] = oi
                    diag = oi["bounds"]["diagonal"]
                    # the Duck's node scales by 0.01; compare bounds relative to diagonal after normalising
                    s = j["bounds"]["diagonal"] / diag if diag else 1
                    if abs(s - 1) > 1e-3 and abs(s - 100) > 0.1 and abs(s - 0.01) > 1e-4: return "bounds diagonal %g vs orig %g" % (j["bounds"]["diagonal"], diag)
                return ""
        elif c.startswith("convert_"):
            ext = c.split("_")[1]; o = os.path.join(d, "out." + ext); outs = [o]
            rc, out, err = run(["convert", f, o])
            def verify(o=o, ext=ext):
                j, e = info(o)
                if j is None: return "output unreadable: " + e
                msg = count_check(v, j, "re-read " + ext, strict_vertices=False, one_uv_set=ext != "glb")
                if msg: return msg
                if ext == "glb":
                    vr = subprocess.run(["node", VALIDATOR, o], capture_output=True, text=True) if VALIDATOR else None
                    if vr is not None and vr.returncode != 0: return "validator: " + vr.stdout[-300:] + vr.stderr[-300:]
                src = row.get("_info")
                if src and j["triangles"] != src["triangles"]: return "triangles %d != input %d" % (j["triangles"], src["triangles"])
                if src:
                    lost = [a for a in src["attributes"] if a not in j["attributes"] and not (ext == "ply" and a in ("material", "texcoord1")) and not (ext == "obj" and a == "texcoord1")]
                    if lost: return "attributes lost: %s" % lost
                return ""
        elif c == "simplify":
            o = os.path.join(d, "simp.ply"); outs = [o]
            rc, out, err = run(["simplify", f, "--ratio", "0.5", "-o", o])
            def verify(o=o):
                j, e = info(o)
                if j is None: return "output unreadable: " + e
                src = row.get("_info")
                if src and src["triangles"] > 100 and not (0.3 * src["triangles"] <= j["triangles"] <= 0.55 * src["triangles"]):
                    return "simplified to %d of %d" % (j["triangles"], src["triangles"])
                return ""
        elif c == "lod":
            o = os.path.join(d, "lod"); outs = [o]
            rc, out, err = run(["lod", f, "--levels", "0.5,0.25", "-o", o])
        elif c == "compare":
            rc, out, err = run(["compare", "--json", v.get("orig") or f, f])
            def verify(out=out):
                try: j = json.loads(out)
                except Exception as e: return "bad json %s" % e
                if v.get("same_geometry") or v.get("orig") == f:
                    h = j.get("hausdorff_relative", j.get("hausdorff"))
                    if h is not None and h > 1e-3 and "g_" not in v["name"]: return "hausdorff %g" % h
                return ""
        elif c == "octree":
            o = os.path.join(d, "a.lfo"); outs = [o]
            rc, out, err = run(["octree", "build", f, "-o", o, "--max-triangles", "2000"])
        elif c == "mcoctree":
            o = os.path.join(d, "a.mco"); outs = [o]
            rc, out, err = run(["mcoctree", "build", f, "-o", o, "--resolution", "32"])
        elif c == "strips":
            o = os.path.join(d, "a.lodstrips"); outs = [o]
            rc, out, err = run(["strips", f, "-o", o])
        elif c == "pack":
            o = os.path.join(d, "pack"); outs = [o]
            rc, out, err = run(["pack", f, "--preset", preset, "-o", o])
        row[c] = check(v, c, rc, out, err, outs, verify)
    row.pop("_info", None)
    shutil.rmtree(d, ignore_errors=True)
    print("%-28s %s" % (name, " ".join("%s=%s" % (k, r if len(r) < 12 else r[:10]) for k, r in row.items())), flush=True)

print("\n=== %d failures" % len(failures))
for f in failures: print(f)
json.dump({"matrix": matrix, "failures": failures}, open(os.path.join(VDIR, "results.json"), "w"), indent=1)
shutil.rmtree(work, ignore_errors=True)
