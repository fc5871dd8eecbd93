#!/usr/bin/env python3
"""Pinocchio reference for mimic joints: the TALOS upper body with its grippers' mimic joints
movable, `tests/data/reference/trees/talos_upper_body_mimic.json`.

    ~/.cache/dynamics-gen-bench/venv/bin/python tools/mimic_reference.py   # pin 4.1.0, numpy

1. `tests/data/robots/trees/talos_upper_body_mimic.urdf` is written from
   `talos_upper_body.urdf`: the twelve gripper joints with `<mimic>` (fixed there, as in
   example-robot-data's talos_reduced.urdf) become `revolute`, as they are in
   example-robot-data's talos_full_v2.urdf (same origin, axis and limits). Each gripper is then
   one coordinate, `gripper_{left,right}_joint`, driving six followers (multiplier 1 or -1,
   offset 0).
2. Pinocchio 4.1.0 `buildModelFromUrdf(path, mimic=True)` refuses a mimic joint that comes
   before its leader in its joint order ("The parent joint of the mimic joint is not in the
   kinematic tree"), and urdfdom orders a link's child joints by name, so
   `gripper_left_inner_double_joint` comes before `gripper_left_joint`. The model is therefore
   built from a copy of the file in which the two leaders are renamed
   `gripper_{left,right}_0_joint` (which sorts them first among their siblings); the names
   are mapped back in the JSON. Renaming changes the order of the physical joints inside
   each gripper only, not the order of the coordinates (each gripper has one), and not the
   dynamics.
3. Samples as the other tree references (`README.md` there, seed 2024): per sample, for
   each coordinate in order q ~ U[lower, upper] of its URDF limits; v, a, u ~ U[-2, 2]^nv;
   tau_rand = g + diag(M) * u. Pinocchio 4.1.0's `aba` does not support mimic joints, so
   `a_fd` solves M a = tau_rand - nle with Pinocchio's `crba` and `nonLinearEffects`
   (numpy, Cholesky).
4. `checks`: Pinocchio's mimic model against the model without mimic (every joint
   independent, from the un-renamed file) projected by hand: q_full = J q + o,
   M = Jᵀ M_full J, nle = Jᵀ nle_full, g = Jᵀ g_full, tau = Jᵀ tau_full(q, J v, J a).
"""

import hashlib
import json
import os
import re
import tempfile

import numpy as np
import pinocchio as pin

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(os.path.dirname(HERE), "tests", "data")
SOURCE = os.path.join(DATA, "robots", "trees", "talos_upper_body.urdf")
URDF = os.path.join(DATA, "robots", "trees", "talos_upper_body_mimic.urdf")
OUT = os.path.join(DATA, "reference", "trees", "talos_upper_body_mimic.json")
LEADERS = {"gripper_left_joint": "gripper_left_0_joint", "gripper_right_joint": "gripper_right_0_joint"}
SEED = 2024
SAMPLES = 20


def movable_mimics(text):
    """The URDF with every fixed joint that has a <mimic> made revolute."""
    def fix(m):
        block = m.group(0)
        return block.replace('type="fixed"', 'type="revolute"', 1) if "<mimic" in block else block
    return re.sub(r'<joint name="[^"]*" type="fixed">.*?</joint>', fix, text, flags=re.S)


def sha256(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def full(m):
    """M from Pinocchio's upper triangle."""
    return np.triu(m) + np.triu(m, 1).T


def main():
    with open(SOURCE) as f:
        text = movable_mimics(f.read())
    with open(URDF, "w") as f:
        f.write(text)
    renamed = text
    for old, new in LEADERS.items():
        renamed = renamed.replace(f'"{old}"', f'"{new}"')
    back = {new: old for old, new in LEADERS.items()}
    with tempfile.NamedTemporaryFile("w", suffix=".urdf", delete=False) as f:
        f.write(renamed)
        renamed_path = f.name
    model = pin.buildModelFromUrdf(renamed_path, mimic=True)
    os.unlink(renamed_path)
    physical = pin.buildModelFromUrdf(URDF)  # every joint independent, original names
    data, pdata = model.createData(), physical.createData()
    name = lambda i: back.get(model.names[i], model.names[i])

    # The coordinates (joints with nv = 1) and the mimic joints, in Pinocchio's order.
    joints = list(range(1, model.njoints))
    coords = [i for i in joints if model.joints[i].nv == 1]
    assert [model.joints[i].idx_v for i in coords] == list(range(model.nv))
    mimics = []
    for k, (mimicking, mimicked) in enumerate(zip(model.mimicking_joints, model.mimicked_joints)):
        j = model.joints[mimicking]
        mimics.append({
            "name": name(mimicking),
            "leader": name(mimicked),
            "multiplier": float(j.extract().scaling),
            "offset": float(j.extract().offset),
        })
    # J and o in the physical model's order.
    jmat = np.zeros((physical.nv, model.nv))
    offset = np.zeros(physical.nq)
    mimic_of = {m["name"]: m for m in mimics}
    coord_index = {name(i): model.joints[i].idx_v for i in coords}
    for i in range(1, physical.njoints):
        n = physical.names[i]
        v = physical.joints[i].idx_v
        if n in mimic_of:
            m = mimic_of[n]
            jmat[v, coord_index[m["leader"]]] = m["multiplier"]
            offset[v] = m["offset"]
        else:
            jmat[v, coord_index[n]] = 1.0

    lower = [float(model.lowerPositionLimit[model.joints[i].idx_q]) for i in coords]
    upper = [float(model.upperPositionLimit[model.joints[i].idx_q]) for i in coords]
    rng = np.random.default_rng(SEED)
    samples = []
    worst = {k: 0.0 for k in ["M_vs_JT_M_full_J", "nle_vs_JT_nle_full", "g_vs_JT_g_full",
                              "tau_vs_JT_tau_full", "M_a_plus_nle_minus_tau", "M_afd_plus_nle_minus_tau_rand"]}
    min_eig = np.inf
    for _ in range(SAMPLES):
        q = np.array([rng.uniform(lo, hi) for lo, hi in zip(lower, upper)])
        v = rng.uniform(-2, 2, model.nv)
        a = rng.uniform(-2, 2, model.nv)
        u = rng.uniform(-2, 2, model.nv)
        tau = pin.rnea(model, data, q, v, a).copy()
        M = full(pin.crba(model, data, q).copy())
        nle = pin.nonLinearEffects(model, data, q, v).copy()
        g = pin.computeGeneralizedGravity(model, data, q).copy()
        tau_rand = g + np.diag(M) * u
        a_fd = np.linalg.solve(M, tau_rand - nle)
        np.linalg.cholesky(M)
        min_eig = min(min_eig, float(np.linalg.eigvalsh(M).min()))
        pin.forwardKinematics(model, data, q)
        o_m_i = {name(i): data.oMi[i].homogeneous.tolist() for i in joints}
        # The same state on the physical model.
        qf, vf, af = jmat @ q + offset, jmat @ v, jmat @ a
        Mf = full(pin.crba(physical, pdata, qf).copy())
        checks = {
            "M_vs_JT_M_full_J": M - jmat.T @ Mf @ jmat,
            "nle_vs_JT_nle_full": nle - jmat.T @ pin.nonLinearEffects(physical, pdata, qf, vf),
            "g_vs_JT_g_full": g - jmat.T @ pin.computeGeneralizedGravity(physical, pdata, qf),
            "tau_vs_JT_tau_full": tau - jmat.T @ pin.rnea(physical, pdata, qf, vf, af),
            "M_a_plus_nle_minus_tau": M @ a + nle - tau,
            "M_afd_plus_nle_minus_tau_rand": M @ a_fd + nle - tau_rand,
        }
        for k, x in checks.items():
            worst[k] = max(worst[k], float(np.abs(x).max()))
        samples.append({
            "q": q.tolist(), "v": v.tolist(), "a": a.tolist(), "tau": tau.tolist(), "M": M.tolist(),
            "nle": nle.tolist(), "g": g.tolist(), "c": (nle - g).tolist(), "tau_rand": tau_rand.tolist(),
            "a_fd": a_fd.tolist(),
            "oMi": [o_m_i[physical.names[i]] for i in range(1, physical.njoints)],
        })
    assert all(x < 1e-11 for x in worst.values()), worst
    out = {
        "schema": "robot-dynamics-reference-mimic/1",
        "robot": "talos_upper_body_mimic",
        "description": "PAL TALOS upper body on a fixed pelvis (talos_upper_body.urdf) with the twelve gripper joints that carry <mimic> movable (revolute, as in example-robot-data's talos_full_v2.urdf): each gripper is one coordinate, gripper_{left,right}_joint, with six mimic joints (multiplier 1 or -1, offset 0).",
        "source": "tests/data/robots/trees/talos_upper_body.urdf (example-robot-data 6.0.0 talos_reduced.urdf, legs locked), mimic joints made revolute by tools/mimic_reference.py",
        "urdf": "robots/trees/talos_upper_body_mimic.urdf",
        "urdf_sha256": sha256(URDF),
        "generator": {
            "script": "tools/mimic_reference.py",
            "pinocchio": pin.__version__,
            "numpy": np.__version__,
            "seed": SEED,
            "model": "pin.buildModelFromUrdf(path, mimic=True) on a copy with the leaders renamed gripper_{left,right}_0_joint (Pinocchio 4.1.0 needs a leader before its followers in its joint order); names mapped back",
            "sampler": "rng = numpy.random.default_rng(seed); per sample: for each coordinate in order q ~ U[lower, upper]; v ~ U[-2,2]^nv; a ~ U[-2,2]^nv; u ~ U[-2,2]^nv; tau_rand = g + diag(M)*u",
            "a_fd": "numpy.linalg.solve(M, tau_rand - nle) with Pinocchio's crba and nonLinearEffects (Pinocchio 4.1.0's aba does not support mimic joints)",
        },
        "gravity": [0.0, 0.0, -9.81],
        "floating": False,
        "nq": model.nq,
        "nv": model.nv,
        "coordinate_names": [name(i) for i in coords],
        "joint_names": [physical.names[i] for i in range(1, physical.njoints)],
        "joint_names_note": "every physical joint, in the order of the un-renamed file (urdfdom/Pinocchio order of talos_upper_body_mimic.urdf); oMi follows it",
        "mimic": mimics,
        "q_sampling_range": {name(i): [lo, hi] for i, lo, hi in zip(coords, lower, upper)},
        "conventions": {
            "q": "the coordinates' positions, in coordinate_names order; a mimic joint's position is multiplier * q[leader] + offset",
            "v": "the coordinates' rates (a mimic joint's rate is multiplier * v[leader])",
            "M": "crba(q), nv x nv over the coordinates (= J^T M_full J), lower triangle mirrored",
            "tau": "rnea(q, v, a) = M a + nle, the generalized force on each coordinate (= J^T tau_full)",
            "oMi": "pose in the world of each joint frame (= child link frame) of joint_names, mimic joints included",
        },
        "checks": {**worst, "min_eig_M": min_eig, "M_symmetric_positive_definite": True},
        "samples": samples,
    }
    with open(OUT, "w") as f:
        json.dump(out, f, indent=1)
        f.write("\n")
    print(f"wrote {os.path.relpath(OUT)}: nq {model.nq}, {len(mimics)} mimic joints; checks {worst}")


if __name__ == "__main__":
    main()
