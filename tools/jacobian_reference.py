#!/usr/bin/env python3
"""Pinocchio's frame Jacobians (and, for the Panda, dynamics with armature) for the serial
robots of tests/data/reference.

For each robot of tests/data/reference/<robot>.json (ur5, panda, rand7, double_pendulum:
their URDFs in tests/data/robots, their samples made by Pinocchio 4.1.0), this writes
tests/data/reference/<robot>.jacobians.json with, for every sample q of that file, the
Jacobians of the file's `ee_frame` in pin.WORLD and pin.LOCAL (6 x nv, Pinocchio's row order
(v, w)). For the Panda it also stores one armature case: model.armature = 0.1*(i+1) kg m^2 on
joint i (0-based), and for the first ten samples rnea(q, qd, qdd), crba(q) (full symmetric)
and aba(q, qd, tau) with tau = the sample's tau_rand.

    ~/.cache/dynamics-gen-bench/venv/bin/python tools/jacobian_reference.py   # pin==4.1.0
"""
import hashlib
import json
import os
import sys

import numpy as np
import pinocchio as pin

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.join(ROOT, "tests", "data")
ARMATURE_ROBOT = "panda"
ARMATURE_SAMPLES = 10


def rows(m):
    return [[float(x) for x in row] for row in np.asarray(m)]


def vec(v):
    return [float(x) for x in np.asarray(v).ravel()]


def frame_id(model, name):
    if model.existFrame(name, pin.BODY):
        return model.getFrameId(name, pin.BODY)
    return model.getFrameId(name)


def sha256(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def armature_case(model, ref):
    arm = np.array([0.1 * (i + 1) for i in range(model.nv)])
    model_arm = model.copy()
    model_arm.armature = arm
    data, data_arm = model.createData(), model_arm.createData()
    samples, worst = [], {"M_arm_minus_M_minus_diag": 0.0, "tau_arm_minus_tau_minus_arm_a": 0.0,
                          "aba_rnea_roundtrip": 0.0, "M_a_plus_nle_minus_tau": 0.0}
    for s in ref["samples"][:ARMATURE_SAMPLES]:
        q, v, a = np.array(s["q"]), np.array(s["qd"]), np.array(s["qdd"])
        tau_in = np.array(s["tau_rand"])
        tau = pin.rnea(model_arm, data_arm, q, v, a).copy()
        m = pin.crba(model_arm, data_arm, q).copy()
        m = np.triu(m) + np.triu(m, 1).T
        a_fd = pin.aba(model_arm, data_arm, q, v, tau_in).copy()
        # Cross-checks against the model without armature and within the armature model.
        m0 = pin.crba(model, data, q).copy()
        m0 = np.triu(m0) + np.triu(m0, 1).T
        tau0 = pin.rnea(model, data, q, v, a).copy()
        nle = pin.nonLinearEffects(model_arm, data_arm, q, v).copy()
        back = pin.aba(model_arm, data_arm, q, v, tau).copy()
        worst["M_arm_minus_M_minus_diag"] = max(worst["M_arm_minus_M_minus_diag"], float(np.abs(m - m0 - np.diag(arm)).max()))
        worst["tau_arm_minus_tau_minus_arm_a"] = max(worst["tau_arm_minus_tau_minus_arm_a"], float(np.abs(tau - tau0 - arm * a).max()))
        worst["aba_rnea_roundtrip"] = max(worst["aba_rnea_roundtrip"], float(np.abs(back - a).max()))
        worst["M_a_plus_nle_minus_tau"] = max(worst["M_a_plus_nle_minus_tau"], float(np.abs(m @ a + nle - tau).max()))
        samples.append({"q": s["q"], "qd": s["qd"], "qdd": s["qdd"], "tau_in": s["tau_rand"],
                        "tau": vec(tau), "M": rows(m), "qdd_fd": vec(a_fd)})
    return {
        "armature": vec(arm),
        "note": "model.armature = 0.1*(i+1) kg m^2 on joint i (0-based); Pinocchio adds it to M's diagonal "
                "(M_arm = M + diag(armature), tau_arm = tau + armature*qdd). Ours: Joint.rotor_inertia = armature, gear_ratio = 1.",
        "samples_from": "the first %d samples of %s.json (q, qd, qdd, tau_in = tau_rand)" % (ARMATURE_SAMPLES, ARMATURE_ROBOT),
        "fields": {"tau": "rnea(q, qd, qdd) with armature", "M": "crba(q) with armature, full symmetric",
                   "qdd_fd": "aba(q, qd, tau_in) with armature"},
        "checks": worst,
        "samples": samples,
    }


def main(robots):
    for robot in robots:
        ref = json.load(open(os.path.join(DATA, "reference", robot + ".json")))
        urdf = os.path.join(DATA, ref["urdf"])
        model = pin.buildModelFromUrdf(urdf)
        assert (model.nq, model.nv) == (ref["nq"], ref["nv"]), (robot, model.nq, model.nv)
        assert model.nq == model.nv, robot  # the configurations below are the samples' q
        names = [model.names[i] for i in range(1, model.njoints)]
        assert names == ref["joint_names"], (robot, names)
        data = model.createData()
        fid = frame_id(model, ref["ee_frame"])
        samples, pose_diff = [], 0.0
        for s in ref["samples"]:
            q = np.array(s["q"])
            pin.computeJointJacobians(model, data, q)
            pin.updateFramePlacements(model, data)
            pose_diff = max(pose_diff, float(np.abs(data.oMf[fid].homogeneous - np.array(s["oMf"])).max()))
            samples.append({
                "q": s["q"],
                "J_world": rows(pin.getFrameJacobian(model, data, fid, pin.WORLD)),
                "J_local": rows(pin.getFrameJacobian(model, data, fid, pin.LOCAL)),
            })
        out = {
            "schema": "robot-jacobians-reference/1",
            "robot": robot,
            "urdf": ref["urdf"],
            "urdf_sha256": sha256(urdf),
            "generator": {
                "script": "tools/jacobian_reference.py",
                "pinocchio": pin.__version__,
                "numpy": np.__version__,
                "samples": "the q of every sample of %s.json (no new random numbers)" % robot,
            },
            "ee_frame": ref["ee_frame"],
            "joint_names": names,
            "nv": model.nv,
            "conventions": {
                "row_order": "Pinocchio's (v, w): rows 0..3 linear, 3..6 angular; dynamics-gen / Modern Robotics use (w, v), so swap the row blocks",
                "J_world": "getFrameJacobian(.., WORLD): the spatial twist in the world frame, v of the point at the world origin (= Modern Robotics J_s, rows swapped)",
                "J_local": "getFrameJacobian(.., LOCAL): the frame's twist in the frame itself (= Modern Robotics J_b, rows swapped)",
                "columns": "one per joint, in joint_names order",
            },
            "checks": {"oMf_max_abs_diff_vs_reference_file": pose_diff},
            "samples": samples,
        }
        if robot == ARMATURE_ROBOT:
            out["armature_case"] = armature_case(model, ref)
        path = os.path.join(DATA, "reference", robot + ".jacobians.json")
        with open(path, "w") as f:
            json.dump(out, f, indent=None, separators=(",", ":"))
            f.write("\n")
        print(path, len(samples), "samples, oMf diff", pose_diff,
              out.get("armature_case", {}).get("checks", ""))


if __name__ == "__main__":
    main(sys.argv[1:] or ["ur5", "panda", "rand7", "double_pendulum"])
