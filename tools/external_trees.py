#!/usr/bin/env python3
"""Tries the CLI `eval` as a new user would on example-robot-data URDFs that are not in the
repository (quadrupeds and humanoids on a free-flyer base) against Pinocchio: 5 random
states each, inverse dynamics, mass matrix and forward dynamics, (v, ω) order mapped.

    /tmp/pinvenv/bin/pip install pin==4.1.0 example-robot-data
    cargo build --release -p dynamics-gen
    /tmp/pinvenv/bin/python tools/external_trees.py
"""
import json, os, subprocess
import numpy as np
import pinocchio as pin
import site
R = next(os.path.join(p, "cmeel.prefix/share/example-robot-data/robots/") for p in site.getsitepackages() if os.path.isdir(os.path.join(p, "cmeel.prefix/share/example-robot-data/robots")))
cases = [("anymal_c_simple_description/urdf/anymal.urdf", True), ("go1_description/urdf/go1.urdf", True),
         ("romeo_description/urdf/romeo_small.urdf", True), ("tiago_description/robots/tiago.urdf", False),
         ("b1_description/urdf/b1.urdf", True), ("talos_data/robots/talos_reduced.urdf", True), ("g1_description/urdf/g1_29dof_with_hand_rev_1_0.urdf", True), ("h1_description/urdf/h1.urdf", True), ("bolt_description/robots/bolt.urdf", True)]
rng = np.random.default_rng(7)
def perm(nv, fl):
    p = list(range(nv))
    if fl: p[0:3], p[3:6] = [3,4,5], [0,1,2]
    return p
for rel, fl in cases:
    path = R + rel
    if not os.path.exists(path): print("missing", rel); continue
    m = pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer()) if fl else pin.buildModelFromUrdf(path)
    if m.nq != m.nv + (1 if fl else 0): print(rel, "has continuous joints (nq)", m.nq, m.nv); continue
    d = m.createData()
    lines, refs = [], []
    for k in range(5):
        q = rng.uniform(-1, 1, m.nq)
        if fl: q[3:7] /= np.linalg.norm(q[3:7])
        v, a = rng.uniform(-1, 1, m.nv), rng.uniform(-1, 1, m.nv)
        tau = pin.rnea(m, d, q, v, a).copy(); M = pin.crba(m, d, q).copy(); M = np.triu(M) + np.triu(M, 1).T
        p = perm(m.nv, fl)
        lines.append(json.dumps({"q": q.tolist(), "qd": v[p].tolist(), "qdd": a[p].tolist(), "tau": tau[p].tolist()}))
        refs.append((tau[p], M[np.ix_(p, p)], a[p]))
    cmd = [os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "target/release/dynamics-gen"), "eval", path] + (["--floating-base"] if fl else [])
    out = subprocess.run(cmd, input="\n".join(lines) + "\n", capture_output=True, text=True)
    if out.returncode != 0: print(rel, "ERROR", out.stderr[:300]); continue
    worst = [0, 0, 0]
    for line, (tau, M, a) in zip(out.stdout.splitlines(), refs):
        o = json.loads(line)
        for i, (x, y) in enumerate([(np.array(o["inverse_dynamics"]), tau), (np.array(o["mass_matrix"]), M), (np.array(o["forward_dynamics"]), a)]):
            worst[i] = max(worst[i], np.abs(x - y).max() / np.abs(y).max())
    print(f"{rel}: nv {m.nv} floating {fl}: worst relative tau {worst[0]:.1e} M {worst[1]:.1e} fd {worst[2]:.1e}")
