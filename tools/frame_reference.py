#!/usr/bin/env python3
"""Pinocchio's numbers for the named frames of the kinematic trees in tests/data.

For each tree of tests/data/robots/trees (the models and the random configurations of
tests/data/reference/trees/<robot>.json, made by Pinocchio 4.1.0), this writes
tests/data/reference/trees/<robot>.frames.json: for every leaf link of the URDF (a link that
no joint hangs from, the default frames of dynamics-gen on a tree) and every sample q, the
link's placement oMf and its Jacobians in pin.LOCAL and pin.WORLD (6 x nv, Pinocchio's row
order (v, w) and velocity order: free flyer (v_b, w_b) first).

    ~/.cache/dynamics-gen-bench/venv/bin/python tools/frame_reference.py   # pin==4.1.0
"""
import json
import os
import sys
import xml.etree.ElementTree as ET

import numpy as np
import pinocchio as pin

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.join(ROOT, "tests", "data")


def leaves(urdf):
    r = ET.parse(urdf).getroot()
    parents = {j.find("parent").get("link") for j in r.findall("joint")}
    return [l.get("name") for l in r.findall("link") if l.get("name") not in parents]


def rows(m):
    return [[float(x) for x in row] for row in np.asarray(m)]


def main(robots):
    for robot in robots:
        ref_path = os.path.join(DATA, "reference", "trees", robot + ".json")
        ref = json.load(open(ref_path))
        urdf = os.path.join(DATA, "robots", "trees", robot + ".urdf")
        if ref["floating"]:
            model = pin.buildModelFromUrdf(urdf, pin.JointModelFreeFlyer())
        else:
            model = pin.buildModelFromUrdf(urdf)
        assert model.nv == ref["nv"], (robot, model.nv, ref["nv"])
        data = model.createData()
        names = [n for n in leaves(urdf) if model.existFrame(n, pin.BODY)]
        ids = [model.getFrameId(n, pin.BODY) for n in names]
        samples = []
        for s in ref["samples"]:
            q = np.array(s["q"])
            pin.computeJointJacobians(model, data, q)
            pin.updateFramePlacements(model, data)
            samples.append(
                {
                    "q": s["q"],
                    "oMf": [rows(data.oMf[i].homogeneous) for i in ids],
                    "J_local": [rows(pin.getFrameJacobian(model, data, i, pin.LOCAL)) for i in ids],
                    "J_world": [rows(pin.getFrameJacobian(model, data, i, pin.WORLD)) for i in ids],
                }
            )
        out = {
            "schema": "robot-frames-reference/1",
            "robot": robot,
            "urdf": "../../robots/trees/" + robot + ".urdf",
            "floating": ref["floating"],
            "nv": model.nv,
            "generator": {
                "script": "tools/frame_reference.py",
                "pinocchio": pin.__version__,
                "numpy": np.__version__,
                "samples": "the q of every sample of " + robot + ".json",
            },
            "conventions": {
                "frames": "every leaf link of the URDF (no joint has it as parent), in file order; Pinocchio BODY frames",
                "oMf": "4x4 placement of the frame in the world at q",
                "J_local": "getFrameJacobian(.., LOCAL): rows (v, w) of the frame's twist in the frame itself",
                "J_world": "getFrameJacobian(.., WORLD): rows (v, w) of the spatial twist in the world frame (v of the point at the world origin)",
                "columns": "Pinocchio's velocity order; a free flyer's six columns are (v_b, w_b) in the base frame",
            },
            "frames": names,
            "samples": samples,
        }
        path = os.path.join(DATA, "reference", "trees", robot + ".frames.json")
        with open(path, "w") as f:
            json.dump(out, f, indent=None, separators=(",", ":"))
            f.write("\n")
        print(path, len(names), "frames", len(samples), "samples")


if __name__ == "__main__":
    main(sys.argv[1:] or ["talos_upper_body", "solo12", "g1_29dof"])
