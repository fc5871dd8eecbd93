#!/usr/bin/env python3
"""Pinocchio's joint-torque regressor, for the robots of tests/data/reference and the seeded
random serial chains of random_chains.derivatives.json.

For each sample Pinocchio 4.1.0 computes

    Y    computeJointTorqueRegressor(q, v, a)   (nv x 10 * (njoints - 1))
    pi   model.inertias[i].toDynamicParameters() for every joint i = 1.., concatenated
         (m, m c_x, m c_y, m c_z, I_xx, I_xy, I_yy, I_xz, I_yz, I_zz), each in joint i's
         frame, I about its origin
    tau  rnea(q, v, a)

and checks Y pi = tau (stored in `checks`; the script fails above 1e-10 relative). The
states are the stored ones: no new random numbers.

Files written (compact JSON):

* tests/data/reference/<robot>.regressor.json for ur5, panda, rand7, double_pendulum: the
  first 3 samples of <robot>.json (q, qd, qdd).
* tests/data/reference/trees/<robot>.regressor.json for talos_upper_body (fixed base),
  solo12 and g1_29dof (free flyer): the first 2 samples of trees/<robot>.json.
* tests/data/reference/random_chains.regressor.json: the 120 chains of
  random_chains.derivatives.json (their URDF text is there), the first stored state each.

    ~/.cache/dynamics-gen-bench/venv/bin/python tools/regressor_reference.py   # pin==4.1.0
"""
import hashlib
import json
import os

import numpy as np
import pinocchio as pin

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REF = os.path.join(ROOT, "tests", "data", "reference")
DATA = os.path.join(ROOT, "tests", "data")
SERIAL = ["ur5", "panda", "rand7", "double_pendulum"]
TREES = ["talos_upper_body", "solo12", "g1_29dof"]
SERIAL_SAMPLES = 3
TREE_SAMPLES = 2
TOL = 1e-10

CONVENTIONS = {
    "Y": "row-major nested lists, nv x 10*(njoints-1); column 10*(i-1)+k is d tau / d pi_{i,k}",
    "parameters": "per Pinocchio joint i = 1.. (a free flyer's root_joint first): Inertia.toDynamicParameters() = "
                  "(m, m c_x, m c_y, m c_z, I_xx, I_xy, I_yy, I_xz, I_yz, I_zz) in joint i's frame, I about its origin",
    "free_flyer": "floating robots: q = [x, y, z, qx, qy, qz, qw, joints]; v and the rows of Y: [v_lin, omega, joints] "
                  "(linear first, in the base frame)",
}


def rows(m):
    return [[float(x) for x in r] for r in np.asarray(m)]


def vec(v):
    return [float(x) for x in np.asarray(v).ravel()]


def sha256(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def parameters(model):
    return np.concatenate([model.inertias[i].toDynamicParameters() for i in range(1, model.njoints)])


def sample(model, q, v, a, worst):
    data = model.createData()
    y = np.asarray(pin.computeJointTorqueRegressor(model, data, q, v, a)).copy().reshape(model.nv, -1)
    pi = parameters(model)
    tau = pin.rnea(model, model.createData(), q, v, a).copy()
    err = np.abs(y @ pi - tau).max() / (np.abs(tau).max() + 1.0)
    assert err <= TOL, err
    worst[0] = max(worst[0], err)
    return {"q": vec(q), "v": vec(v), "a": vec(a), "tau": vec(tau), "Y": rows(y)}


def write(path, out):
    with open(path, "w") as f:
        json.dump(out, f, indent=None, separators=(",", ":"))
        f.write("\n")
    print(path, "%.0f kB" % (os.path.getsize(path) / 1e3), out["checks"])


def header(robot, urdf, floating, model, worst, what):
    return {
        "schema": "robot-regressor-reference/1",
        "robot": robot,
        "urdf": os.path.relpath(urdf, DATA) if urdf else None,
        "urdf_sha256": sha256(urdf) if urdf else None,
        "floating": floating,
        "generator": {"script": "tools/regressor_reference.py", "pinocchio": pin.__version__,
                      "numpy": np.__version__, "samples": what},
        "joint_names": [model.names[i] for i in range(1, model.njoints)],
        "nq": model.nq,
        "nv": model.nv,
        "gravity": vec(model.gravity.linear),
        "parameters": vec(parameters(model)),
        "conventions": CONVENTIONS,
        "checks": {"max_rel_Y_pi_minus_rnea": worst[0], "required": TOL},
    }


def serial(robot):
    ref = json.load(open(os.path.join(REF, robot + ".json")))
    urdf = os.path.join(DATA, ref["urdf"])
    model = pin.buildModelFromUrdf(urdf)
    worst = [0.0]
    samples = [sample(model, *(np.array(s[k]) for k in ("q", "qd", "qdd")), worst)
               for s in ref["samples"][:SERIAL_SAMPLES]]
    out = header(robot, urdf, False, model, worst,
                 "the first %d samples of %s.json (q, v = qd, a = qdd)" % (SERIAL_SAMPLES, robot))
    out["samples"] = samples
    write(os.path.join(REF, robot + ".regressor.json"), out)


def tree(robot):
    ref = json.load(open(os.path.join(REF, "trees", robot + ".json")))
    urdf = os.path.join(DATA, ref["urdf"])
    model = (pin.buildModelFromUrdf(urdf, pin.JointModelFreeFlyer()) if ref["floating"]
             else pin.buildModelFromUrdf(urdf))
    worst = [0.0]
    samples = [sample(model, *(np.array(s[k]) for k in ("q", "v", "a")), worst)
               for s in ref["samples"][:TREE_SAMPLES]]
    out = header(robot, urdf, ref["floating"], model, worst,
                 "the first %d samples of trees/%s.json (q, v, a)" % (TREE_SAMPLES, robot))
    out["samples"] = samples
    write(os.path.join(REF, "trees", robot + ".regressor.json"), out)


def chains():
    src = json.load(open(os.path.join(REF, "random_chains.derivatives.json")))
    worst, out = [0.0], []
    for c in src["chains"]:
        model = pin.buildModelFromXML(c["urdf"])
        s = c["samples"][0]
        smp = sample(model, *(np.array(s[k]) for k in ("q", "v", "a")), worst)
        out.append({"name": c["name"], "nv": model.nv, "parameters": vec(parameters(model)), "sample": smp})
    write(os.path.join(REF, "random_chains.regressor.json"), {
        "schema": "robot-regressor-reference/1",
        "generator": {"script": "tools/regressor_reference.py", "pinocchio": pin.__version__,
                      "numpy": np.__version__,
                      "samples": "the chains of random_chains.derivatives.json (URDF text there), first state each"},
        "conventions": CONVENTIONS,
        "checks": {"max_rel_Y_pi_minus_rnea": worst[0], "required": TOL},
        "chains": out,
    })


if __name__ == "__main__":
    for r in SERIAL:
        serial(r)
    for r in TREES:
        tree(r)
    chains()
