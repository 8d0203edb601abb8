#!/usr/bin/env python3
"""freemesh --blocks beside Gmsh's quasi-structured quads (Mesh.Algorithm 11) on the public domains.

usage (from the project root, after `cargo build --release`; the judge's venv):
    /tmp/venv/bin/python tests/outside/blocks_vs_gmsh.py [--set public|DIR] [--runs 3]

For each domain, uniform at its size: freemesh's whole process (`freemesh mesh D --blocks -o
out.msh`, best of --runs) and Gmsh's generate(2) alone (best of --runs, each in its own process,
geometry and boundary counts from the bench's gmsh_geometry.build, as the judge's Gmsh runs).
Both meshes are judged by the bench's meshtools: valid, within the paper's bounds (corners in
[min(45, sharpest input corner), 135], aspect and taper <= 10, size jump <= 2), n_irregular
(interior nodes whose valence is not 4). A domain counts as "fewer" when ours has no more
irregular nodes and fewer quads than Gmsh's, and "10x" when our whole process is at least ten
times faster than Gmsh's generate(2). Gmsh's quasi-structured mesher splits every boundary
segment in two, so its meshes have about four times our quads.
Last line: '<fewer>/<total> fewer irregular nodes and quads, <fast>/<total> 10x faster,
<within>/<total> ours within the bounds'."""
import argparse, json, os, subprocess, sys, tempfile, time

HERE = os.path.dirname(os.path.abspath(__file__))
BENCH = os.path.abspath(os.path.join(HERE, "..", "..", "..", "shared", "bench"))
sys.path.insert(0, BENCH)
import meshtools as mt  # noqa: E402

GMSH = r'''
import sys, json, time
sys.path.insert(0, sys.argv[1])
import gmsh, gmsh_geometry
dom, h, out = sys.argv[2], float(sys.argv[3]), sys.argv[4]
gmsh.initialize(); gmsh.option.setNumber("General.Terminal", 0)
gmsh_geometry.build(dom, h)
gmsh.option.setNumber("Mesh.MeshSizeMin", 0); gmsh.option.setNumber("Mesh.MeshSizeMax", 1e22)
gmsh.option.setNumber("Mesh.Algorithm", 11)
t0 = time.perf_counter(); gmsh.model.mesh.generate(2); dt = time.perf_counter() - t0
gmsh.write(out); gmsh.finalize()
print(json.dumps(dict(seconds=dt)))
'''


def judge(path, domain):
    pts, quads, other = mt.read_mesh(path)
    v, q = mt.validity(pts, quads, other, domain)
    _, _, loops, _ = mt.load_domain(domain)
    cmin = min(mt.corner_angles(loops) or [90])
    within = (q["min_angle"] >= min(45.0, cmin) - 0.5 and q["max_angle"] <= 135.5 and q["max_aspect"] <= 10
              and q["max_taper"] <= 10 and q["max_size_jump"] <= 2.0)
    return dict(valid=bool(v["valid"]), within=bool(v["valid"] and within), quads=q["quads"],
                n_irregular=q["n_irregular"], min_angle=round(q["min_angle"], 1), max_angle=round(q["max_angle"], 1))


def best_of(runs, f):
    best, last = None, None
    for _ in range(runs):
        t, last = f()
        if t is None:
            return None, last
        best = t if best is None else min(best, t)
    return best, last


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--set", default="public"); ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--bin", default="target/release/freemesh")
    a = ap.parse_args()
    files = mt.domain_files(a.set, BENCH)
    tmp = tempfile.mkdtemp(prefix="blocks_")
    fewer = fast = within = 0
    for f in files:
        name = os.path.basename(f)[:-5]; h = json.load(open(f))["size"]
        ours, theirs = os.path.join(tmp, name + ".msh"), os.path.join(tmp, name + ".qs.msh")

        def run_ours():
            t0 = time.perf_counter()
            p = subprocess.run([a.bin, "mesh", f, "-o", ours, "--blocks"], capture_output=True, text=True)
            return (time.perf_counter() - t0, None) if p.returncode == 0 else (None, p.stderr.strip()[-200:])

        def run_gmsh():
            p = subprocess.run([sys.executable, "-c", GMSH, BENCH, f, repr(h), theirs], capture_output=True,
                               text=True, timeout=600)
            if p.returncode != 0:
                return None, p.stderr.strip()[-200:]
            return json.loads(p.stdout.strip().splitlines()[-1])["seconds"], None

        row = dict(domain=name)
        t, err = best_of(a.runs, run_ours)
        row["freemesh"] = dict(error=err) if t is None else dict(judge(ours, f), seconds=round(t, 3))
        t, err = best_of(a.runs, run_gmsh)
        row["gmsh_qs"] = dict(error=err) if t is None else dict(judge(theirs, f), seconds=round(t, 3))
        fm, gq = row["freemesh"], row["gmsh_qs"]
        if "error" not in fm:
            within += fm["within"]
            if "error" in gq or (fm["n_irregular"] <= gq["n_irregular"] and fm["quads"] < gq["quads"]):
                fewer += 1; row["fewer"] = True
            if "error" in gq or 10 * fm["seconds"] <= gq["seconds"]:
                fast += 1; row["ten_times_faster"] = True
        print(json.dumps(row), flush=True)
    n = len(files)
    print(f"{fewer}/{n} fewer irregular nodes and quads, {fast}/{n} 10x faster, {within}/{n} ours within the bounds")


main()
