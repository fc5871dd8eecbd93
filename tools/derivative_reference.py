#!/usr/bin/env python3
"""Pinocchio's derivatives of the dynamics, for the robots of tests/data/reference and for
seeded random serial chains.

For each quantity Pinocchio 4.1.0 computes analytically:

    dtau_dq, dtau_dv  computeRNEADerivatives(q, v, a)         (d tau / d q, d tau / d v)
    ddq_dq, ddq_dv    computeABADerivatives(q, v, tau)        (d a / d q, d a / d v of a = aba(q, v, tau))
    Minv              computeMinverse(q)                       (full symmetric; Pinocchio fills the upper triangle)
    dg_dq             computeGeneralizedGravityDerivatives(q)  (d g / d q)

Derivatives with respect to q are in the tangent space (nv columns): column j is the
derivative along pin.integrate(q, t e_j) at t = 0. Everything is stored in Pinocchio's own
conventions (see `conventions` in each file); the Rust test converts.

Files written (compact JSON):

* tests/data/reference/<robot>.derivatives.json for ur5, panda, rand7, double_pendulum: the
  first SERIAL_SAMPLES samples of <robot>.json (q, qd, qdd; tau = that sample's tau_rand).
* tests/data/reference/trees/<robot>.derivatives.json for talos_upper_body (fixed base), solo12
  and g1_29dof (free flyer): the first TREE_SAMPLES samples of trees/<robot>.json (q, v, a,
  tau = tau_rand).
* tests/data/reference/random_chains.derivatives.json: CHAINS random serial chains (1-8
  joints, revolute and prismatic, random unit or axis-aligned axes, random joint origins,
  random inertias, some fixed joints) drawn by numpy.random.default_rng(SEED), their URDF text
  in the file, CHAIN_STATES random states each.

Every sample is checked in the script (residuals in `checks`): the implicit-function identities
ddq_dq = -Minv dtau_dq and ddq_dv = -Minv dtau_dv at a = aba(q, v, tau), Minv M = I, dg_dq =
dtau_dq at v = a = 0, and central finite differences (step 1e-6, q moved by pin.integrate) of
rnea, aba and computeGeneralizedGravity against the analytic derivatives.

    ~/.cache/dynamics-gen-bench/venv/bin/python tools/derivative_reference.py   # pin==4.1.0
"""
import hashlib
import json
import os
import sys

import numpy as np
import pinocchio as pin

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.join(ROOT, "tests", "data")
SERIAL = ["ur5", "panda", "rand7", "double_pendulum"]
TREES = ["talos_upper_body", "solo12", "g1_29dof"]
SERIAL_SAMPLES = 5
TREE_SAMPLES = 3
CHAINS = 120
CHAIN_STATES = 2
SEED = 20250611
FD_STEP = 1e-6
# Required of every check below (the script fails otherwise); the achieved values are stored.
IDENTITY_TOL = 1e-9   # relative, per matrix: ||x - y||_inf <= tol * ||y||_inf + tol
FD_TOL = 1e-6         # relative, per matrix, central differences at step 1e-6

CONVENTIONS = {
    "matrices": "row-major nested lists, X[i][j] = d f_i / d x_j, nv x nv",
    "tangent_space": "d/dq are nv columns: column j = d/dt f(pin.integrate(q, t e_j)) at t = 0 (for 1-dof joints the plain partial d/dq_j)",
    "free_flyer": "floating robots: q = [x, y, z, qx, qy, qz, qw, joints] (quaternion scalar last); v = [v_lin, omega, joint rates] "
                  "in the base frame (Pinocchio LOCAL, LINEAR FIRST); tau[0:6] = [force, torque] on the base in the base frame; "
                  "pin.integrate moves the base by the SE(3) exponential of the body twist, so the base columns of d/dq are "
                  "derivatives along dp/dt = R v_lin, dR/dt = R [omega]x. dynamics-gen orders the base (omega, v_lin) and "
                  "(torque, force): permute rows and columns 0..3 <-> 3..6 of every matrix.",
    "dtau_dq": "computeRNEADerivatives(q, v, a)[0] at the sample's (q, v, a); a held fixed",
    "dtau_dv": "computeRNEADerivatives(q, v, a)[1]",
    "ddq_dq": "computeABADerivatives(q, v, tau)[0]: d/dq of aba(q, v, tau), tau held fixed",
    "ddq_dv": "computeABADerivatives(q, v, tau)[1]",
    "Minv": "computeMinverse(q), upper triangle mirrored (= computeABADerivatives(q, v, tau)[2])",
    "dg_dq": "computeGeneralizedGravityDerivatives(q) (gravity (0, 0, -9.81) in the world frame)",
}


def rows(m):
    return [[float(x) for x in row] for row in np.asarray(m)]


def vec(v):
    return [float(x) for x in np.asarray(v).ravel()]


def sha256_bytes(b):
    return hashlib.sha256(b).hexdigest()


def sha256(path):
    with open(path, "rb") as f:
        return sha256_bytes(f.read())


def sym(m):
    m = np.array(m)
    return np.triu(m) + np.triu(m, 1).T


def rel(x, y):
    """||x - y||_inf / (||y||_inf + 1): relative for large y, absolute for small."""
    return float(np.abs(x - y).max() / (np.abs(y).max() + 1.0)) if x.size else 0.0


def fd_columns(model, f, q, h=FD_STEP):
    cols = []
    for j in range(model.nv):
        e = np.zeros(model.nv)
        e[j] = h
        cols.append((f(pin.integrate(model, q, e)) - f(pin.integrate(model, q, -e))) / (2 * h))
    return np.array(cols).T


def fd_v(model, f, v, h=FD_STEP):
    cols = []
    for j in range(model.nv):
        e = np.zeros(model.nv)
        e[j] = h
        cols.append((f(v + e) - f(v - e)) / (2 * h))
    return np.array(cols).T


class Worst:
    def __init__(self):
        self.values = {}

    def add(self, name, value, tol):
        assert value <= tol, (name, value, tol)
        self.values[name] = max(self.values.get(name, 0.0), value)


def derivatives(model, q, v, a, tau, worst):
    """The six quantities at one state, and the script's checks of them."""
    data = model.createData()
    dtau_dq, dtau_dv, _ = (x.copy() for x in pin.computeRNEADerivatives(model, data, q, v, a))
    ddq_dq, ddq_dv, minv_aba = (x.copy() for x in pin.computeABADerivatives(model, data, q, v, tau))
    minv = sym(pin.computeMinverse(model, data, q))
    dg_dq = pin.computeGeneralizedGravityDerivatives(model, data, q).copy()
    m = sym(pin.crba(model, data, q))
    nv = model.nv
    # Identities.
    worst.add("Minv_aba_minus_computeMinverse", rel(sym(minv_aba), minv), IDENTITY_TOL)
    worst.add("Minv_M_minus_I", rel(minv @ m, np.eye(nv)), IDENTITY_TOL)
    a_fd = pin.aba(model, data, q, v, tau).copy()
    d_fd = model.createData()
    t_dq, t_dv, _ = (x.copy() for x in pin.computeRNEADerivatives(model, d_fd, q, v, a_fd))
    worst.add("ddq_dq_plus_Minv_dtau_dq_at_aba", rel(ddq_dq, -minv @ t_dq), IDENTITY_TOL)
    worst.add("ddq_dv_plus_Minv_dtau_dv_at_aba", rel(ddq_dv, -minv @ t_dv), IDENTITY_TOL)
    z = np.zeros(nv)
    d_g = model.createData()  # kept alive: the returned arrays are views into it
    g_dq, _, _ = (x.copy() for x in pin.computeRNEADerivatives(model, d_g, q, z, z))
    worst.add("dg_dq_minus_dtau_dq_at_v0_a0", rel(dg_dq, g_dq), IDENTITY_TOL)
    # Central differences (q moved by pin.integrate).
    dd = model.createData()
    worst.add("fd_dtau_dq", rel(fd_columns(model, lambda x: pin.rnea(model, dd, x, v, a).copy(), q), dtau_dq), FD_TOL)
    worst.add("fd_dtau_dv", rel(fd_v(model, lambda x: pin.rnea(model, dd, q, x, a).copy(), v), dtau_dv), FD_TOL)
    worst.add("fd_ddq_dq", rel(fd_columns(model, lambda x: pin.aba(model, dd, x, v, tau).copy(), q), ddq_dq), FD_TOL)
    worst.add("fd_ddq_dv", rel(fd_v(model, lambda x: pin.aba(model, dd, q, x, tau).copy(), v), ddq_dv), FD_TOL)
    worst.add("fd_dg_dq", rel(fd_columns(model, lambda x: pin.computeGeneralizedGravity(model, dd, x).copy(), q), dg_dq),
              FD_TOL)
    return {"dtau_dq": rows(dtau_dq), "dtau_dv": rows(dtau_dv), "ddq_dq": rows(ddq_dq),
            "ddq_dv": rows(ddq_dv), "Minv": rows(minv), "dg_dq": rows(dg_dq)}


def generator(samples):
    return {"script": "tools/derivative_reference.py", "pinocchio": pin.__version__,
            "numpy": np.__version__, "samples": samples}


def checks_doc(worst):
    return {
        "definition": "max over the samples of ||x - y||_inf / (||y||_inf + 1) per matrix; identities required <= %g, "
                      "central differences (step %g, q by pin.integrate) <= %g" % (IDENTITY_TOL, FD_STEP, FD_TOL),
        **worst.values,
    }


def write(path, out):
    with open(path, "w") as f:
        json.dump(out, f, indent=None, separators=(",", ":"))
        f.write("\n")
    print(path, "%.0f kB" % (os.path.getsize(path) / 1e3), json.dumps(out["checks"]))


def serial(robot):
    ref = json.load(open(os.path.join(DATA, "reference", robot + ".json")))
    urdf = os.path.join(DATA, ref["urdf"])
    model = pin.buildModelFromUrdf(urdf)
    assert (model.nq, model.nv) == (ref["nq"], ref["nv"]) and model.nq == model.nv, robot
    names = [model.names[i] for i in range(1, model.njoints)]
    assert names == ref["joint_names"], (robot, names)
    worst, samples, data = Worst(), [], model.createData()
    for s in ref["samples"][:SERIAL_SAMPLES]:
        q, v, a, tau = (np.array(s[k]) for k in ("q", "qd", "qdd", "tau_rand"))
        # The reference file's own numbers, reproduced.
        worst.add("rnea_minus_reference_tau", rel(pin.rnea(model, data, q, v, a).copy(), np.array(s["tau"])),
                  1e-12)
        samples.append({"q": s["q"], "v": s["qd"], "a": s["qdd"], "tau": s["tau_rand"],
                        **derivatives(model, q, v, a, tau, worst)})
    write(os.path.join(DATA, "reference", robot + ".derivatives.json"), {
        "schema": "robot-derivatives-reference/1",
        "robot": robot,
        "urdf": ref["urdf"],
        "urdf_sha256": sha256(urdf),
        "floating": False,
        "generator": generator("the first %d samples of %s.json: q, v = qd, a = qdd, tau = tau_rand (no new random numbers)"
                               % (SERIAL_SAMPLES, robot)),
        "ee_frame": ref["ee_frame"],
        "joint_names": names,
        "nq": model.nq,
        "nv": model.nv,
        "gravity": vec(model.gravity.linear),
        "conventions": CONVENTIONS,
        "checks": checks_doc(worst),
        "samples": samples,
    })


def tree(robot):
    ref = json.load(open(os.path.join(DATA, "reference", "trees", robot + ".json")))
    urdf = os.path.join(DATA, ref["urdf"])
    if ref["floating"]:
        model = pin.buildModelFromUrdf(urdf, pin.JointModelFreeFlyer())
    else:
        model = pin.buildModelFromUrdf(urdf)
    assert (model.nq, model.nv) == (ref["nq"], ref["nv"]), robot
    names = [model.names[i] for i in range(1, model.njoints)]
    assert names == ref["joint_names"], (robot, names)
    worst, samples, data = Worst(), [], model.createData()
    for s in ref["samples"][:TREE_SAMPLES]:
        q, v, a, tau = (np.array(s[k]) for k in ("q", "v", "a", "tau_rand"))
        worst.add("rnea_minus_reference_tau", rel(pin.rnea(model, data, q, v, a).copy(), np.array(s["tau"])),
                  1e-12)
        samples.append({"q": s["q"], "v": s["v"], "a": s["a"], "tau": s["tau_rand"],
                        **derivatives(model, q, v, a, tau, worst)})
    write(os.path.join(DATA, "reference", "trees", robot + ".derivatives.json"), {
        "schema": "robot-derivatives-reference/1",
        "robot": robot,
        "urdf": ref["urdf"],
        "urdf_sha256": sha256(urdf),
        "floating": ref["floating"],
        "generator": generator("the first %d samples of trees/%s.json: q, v, a, tau = tau_rand (no new random numbers)"
                               % (TREE_SAMPLES, robot)),
        "joint_names": names,
        "nq": model.nq,
        "nv": model.nv,
        "gravity": vec(model.gravity.linear),
        "conventions": CONVENTIONS,
        "checks": checks_doc(worst),
        "samples": samples,
    })


# --- random chains ---------------------------------------------------------------------------

def rot(rpy):
    return pin.rpy.rpyToMatrix(np.array(rpy))


def f(x):
    return repr(float(x))


def xyz_rpy(xyz, rpy):
    return 'xyz="%s" rpy="%s"' % (" ".join(map(f, xyz)), " ".join(map(f, rpy)))


def random_axis(rng):
    if rng.uniform() < 0.3:
        axis = np.zeros(3)
        axis[rng.integers(3)] = rng.choice([-1.0, 1.0])
        return axis
    axis = rng.normal(size=3)
    return axis / np.linalg.norm(axis)


def random_inertial(rng):
    """Mass, COM origin (xyz, rpy) and a full inertia tensor (about the COM, in the rotated
    inertial frame): a box's principal moments (triangle inequality strict) in a random
    orientation."""
    mass = rng.uniform(0.2, 5.0)
    xyz = rng.uniform(-0.2, 0.2, 3)
    rpy = rng.uniform(-np.pi, np.pi, 3)
    a, b, c = rng.uniform(0.05, 0.5, 3)
    principal = mass / 12.0 * np.array([b * b + c * c, a * a + c * c, a * a + b * b])
    r0 = rot(rng.uniform(-np.pi, np.pi, 3))
    inertia = r0 @ np.diag(principal) @ r0.T
    inertia = (inertia + inertia.T) / 2
    return mass, xyz, rpy, inertia


def inertial_xml(rng):
    mass, xyz, rpy, i = random_inertial(rng)
    return ('    <inertial>\n      <origin %s/>\n      <mass value="%s"/>\n'
            '      <inertia ixx="%s" ixy="%s" ixz="%s" iyy="%s" iyz="%s" izz="%s"/>\n    </inertial>\n'
            % (xyz_rpy(xyz, rpy), f(mass), f(i[0, 0]), f(i[0, 1]), f(i[0, 2]), f(i[1, 1]), f(i[1, 2]), f(i[2, 2])))


def random_chain(rng, index, dof):
    """URDF text of a serial chain with `dof` movable joints; a fixed joint (to a link with
    its own inertia, which both parsers merge into the body before it) follows a movable one
    with probability 0.2. Returns (urdf, joint types)."""
    name = "chain%03d" % index
    links = ['  <link name="base_link"/>\n']
    joints, types, parent, k = [], [], "base_link", 0
    for i in range(dof):
        kind = "prismatic" if rng.uniform() < 0.3 else "revolute"
        types.append(kind)
        child = "link%d" % (i + 1)
        links.append('  <link name="%s">\n%s  </link>\n' % (child, inertial_xml(rng)))
        origin = xyz_rpy(rng.uniform(-0.3, 0.3, 3), rng.uniform(-np.pi, np.pi, 3))
        axis = random_axis(rng)
        joints.append(
            '  <joint name="joint%d" type="%s">\n    <parent link="%s"/>\n    <child link="%s"/>\n'
            '    <origin %s/>\n    <axis xyz="%s"/>\n'
            '    <limit lower="-100" upper="100" effort="1000" velocity="100"/>\n  </joint>\n'
            % (i + 1, kind, parent, child, origin, " ".join(map(f, axis))))
        parent = child
        if rng.uniform() < 0.2:
            k += 1
            extra = "fixed_link%d" % k
            links.append('  <link name="%s">\n%s  </link>\n' % (extra, inertial_xml(rng)))
            origin = xyz_rpy(rng.uniform(-0.3, 0.3, 3), rng.uniform(-np.pi, np.pi, 3))
            joints.append('  <joint name="fixed%d" type="fixed">\n    <parent link="%s"/>\n    <child link="%s"/>\n'
                          '    <origin %s/>\n  </joint>\n' % (k, parent, extra, origin))
            parent = extra
    text = '<?xml version="1.0"?>\n<robot name="%s">\n%s%s</robot>\n' % (name, "".join(links), "".join(joints))
    return name, text, types


def random_chains():
    rng = np.random.default_rng(SEED)
    worst, chains = Worst(), []
    for index in range(CHAINS):
        dof = 1 + index % 8
        name, text, types = random_chain(rng, index, dof)
        model = pin.buildModelFromXML(text)
        assert (model.nq, model.nv) == (dof, dof), name
        names = [model.names[i] for i in range(1, model.njoints)]
        assert names == ["joint%d" % (i + 1) for i in range(dof)], names
        data = model.createData()
        states = []
        for _ in range(CHAIN_STATES):
            q = np.array([rng.uniform(-np.pi, np.pi) if t == "revolute" else rng.uniform(-0.5, 0.5) for t in types])
            v = rng.uniform(-2, 2, dof)
            a = rng.uniform(-2, 2, dof)
            u = rng.uniform(-2, 2, dof)
            m = sym(pin.crba(model, data, q))
            tau = pin.computeGeneralizedGravity(model, data, q) + np.diag(m) * u
            states.append({"q": vec(q), "v": vec(v), "a": vec(a), "tau": vec(tau),
                           **derivatives(model, q, v, a, tau, worst)})
        chains.append({"name": name, "nv": dof, "joint_types": types, "urdf": text,
                       "urdf_sha256": sha256_bytes(text.encode()), "pinocchio_types":
                       [model.joints[i].shortname() for i in range(1, model.njoints)], "samples": states})
    write(os.path.join(DATA, "reference", "random_chains.derivatives.json"), {
        "schema": "robot-derivatives-reference-random-chains/1",
        "generator": {
            **generator("%d states per chain" % CHAIN_STATES),
            "seed": SEED,
            "sampler": (
                "rng = numpy.random.default_rng(seed); chain k (k = 0..%d) has 1 + k %% 8 movable joints, drawn in this "
                "order per joint: type (prismatic with p 0.3, else revolute), the child link's inertial (mass ~ U[0.2,5] kg, "
                "COM xyz ~ U[-0.2,0.2]^3, inertial rpy ~ U[-pi,pi]^3, box sides a,b,c ~ U[0.05,0.5] m giving principal "
                "moments m(b^2+c^2)/12.., rotated by rpy ~ U[-pi,pi]^3 into a full tensor), joint origin xyz ~ U[-0.3,0.3]^3, "
                "rpy ~ U[-pi,pi]^3, axis (p 0.3: +-x, +-y or +-z, else a normalized standard normal 3-vector), then with "
                "p 0.2 a fixed joint (random origin) to an extra link with its own random inertial, from which the next "
                "joint hangs. Limits [-100, 100], never reached. After each chain, per state: q (revolute ~ U[-pi,pi], "
                "prismatic ~ U[-0.5,0.5]), v ~ U[-2,2], a ~ U[-2,2], u ~ U[-2,2], tau = g(q) + diag(M(q)) * u"
                % (CHAINS - 1)),
        },
        "model": "pin.buildModelFromXML(urdf) (fixed base, gravity (0, 0, -9.81)); dynamics-gen: "
                 "dynamics_model::from_str(urdf, Format::Urdf, name, &LoadOptions::default())",
        "conventions": CONVENTIONS,
        "checks": checks_doc(worst),
        "chains": chains,
    })


def main(args):
    targets = args or SERIAL + TREES + ["random_chains"]
    for t in targets:
        if t in SERIAL:
            serial(t)
        elif t in TREES:
            tree(t)
        elif t == "random_chains":
            random_chains()
        else:
            raise SystemExit("unknown target %r" % t)


if __name__ == "__main__":
    main(sys.argv[1:])
