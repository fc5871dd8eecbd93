#!/usr/bin/env python3
"""Validate dynamics-gen on third-party URDF arms against Pinocchio.

For every robot of a JSON config (see arms.json and README.md):

1. `dynamics-gen joints` (the joint order) and `dynamics-gen eval` on random states, compared
   with Pinocchio: mass matrix (crba), c = nonLinearEffects - g, g, inverse dynamics (rnea),
   forward dynamics (aba), end-effector pose (frame placement of the tip link), and the
   Coriolis matrix (computeCoriolisMatrix; not unique, reported separately with C qd = c).
2. The generated code: a scratch crate outside the repo whose build.rs runs
   `dynamics_gen::Builder` on every robot and whose main evaluates the five generated
   functions on the same states; compared with Pinocchio the same way. Generation time (CLI
   `generate`), generated lines and the crate's release build times are measured.

Tolerance for x against the reference y: ||x - y||_inf <= 1e-9 ||y||_inf + 1e-12.
Needs: numpy and pin (Pinocchio) in the running Python; cargo on PATH.
"""

import argparse
import glob
import json
import os
import shutil
import site
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

import numpy as np
import pinocchio as pin

REL, ABS = 1e-9, 1e-12
QUANTITIES = ["mass_matrix", "coriolis", "gravity", "inverse_dynamics", "forward_dynamics"]


def default_urdf_dir():
    """example-robot-data's robots directory inside the cmeel prefix, if installed."""
    for sp in site.getsitepackages():
        d = os.path.join(sp, "cmeel.prefix", "share", "example-robot-data", "robots")
        if os.path.isdir(d):
            return d
    return None


def cli_options(robot):
    """The --tip/--lock options of a config entry."""
    opts = []
    if robot.get("tip"):
        opts += ["--tip", robot["tip"]]
    for joint, value in robot.get("lock", {}).items():
        opts += ["--lock", f"{joint}={value!r}"]
    return opts


def run(cmd, stdin=None):
    t0 = time.perf_counter()
    p = subprocess.run(cmd, input=stdin, capture_output=True, text=True)
    return p, time.perf_counter() - t0


def tip_link(path, names, tip):
    """Our end-effector link: the --tip, or the child link of the last movable joint."""
    if tip:
        return tip
    root = ET.parse(path).getroot()
    for j in root.findall("joint"):
        if j.get("name") == names[-1]:
            return j.find("child").get("link")
    raise ValueError(f"joint {names[-1]} not found in {path}")


class PinRobot:
    """Pinocchio's model of the same URDF, reduced by the locks, indexed by our joint order."""

    def __init__(self, path, names, locks, tip):
        full = pin.buildModelFromUrdf(path)  # mimic joints parsed as independent joints
        q_ref = pin.neutral(full)
        lock_ids = []
        for jid in range(1, full.njoints):
            name = full.names[jid]
            if name in names:
                continue
            if name not in locks:
                raise ValueError(f"{name} is movable in Pinocchio but neither ours nor locked")
            lock_ids.append(jid)
            self._set(full, q_ref, jid, locks[name])
        self.model = pin.buildReducedModel(full, lock_ids, q_ref) if lock_ids else full
        self.model.gravity.linear = np.array([0.0, 0.0, -9.81])
        self.data = self.model.createData()
        self.joints = [self.model.joints[self.model.getJointId(n)] for n in names]
        self.perm = [j.idx_v for j in self.joints]
        self.frame = self.model.getFrameId(tip, pin.BODY)
        if self.frame >= len(self.model.frames):
            raise ValueError(f"no Pinocchio body frame for tip link {tip}")
        self.continuous = [j.nq == 2 for j in self.joints]

    @staticmethod
    def _set(model, q, jid, value):
        j = model.joints[jid]
        if j.nq == 2:
            q[j.idx_q : j.idx_q + 2] = [np.cos(value), np.sin(value)]
        else:
            q[j.idx_q] = value

    def q_of(self, q_ours):
        q = pin.neutral(self.model)
        for j, v in zip(self.joints, q_ours):
            if j.nq == 2:
                q[j.idx_q : j.idx_q + 2] = [np.cos(v), np.sin(v)]
            else:
                q[j.idx_q] = v
        return q

    def v_of(self, v_ours):
        v = np.zeros(self.model.nv)
        v[self.perm] = v_ours
        return v

    def evaluate(self, s):
        """The reference quantities at a state, in our joint order."""
        m, d, p = self.model, self.data, self.perm
        q, qd, qdd, tau = self.q_of(s["q"]), self.v_of(s["qd"]), self.v_of(s["qdd"]), self.v_of(s["tau"])
        M = pin.crba(m, d, q).copy()
        M = np.triu(M) + np.triu(M, 1).T
        g = pin.computeGeneralizedGravity(m, d, q).copy()
        c = pin.nonLinearEffects(m, d, q, qd).copy() - g
        tau_id = pin.rnea(m, d, q, qd, qdd).copy()
        qdd_fd = pin.aba(m, d, q, qd, tau).copy()
        C = pin.computeCoriolisMatrix(m, d, q, qd).copy()
        pin.framesForwardKinematics(m, d, q)
        T = d.oMf[self.frame].homogeneous.copy()
        ix = np.ix_(p, p)
        return {
            "mass_matrix": M[ix],
            "coriolis": c[p],
            "gravity": g[p],
            "inverse_dynamics": tau_id[p],
            "forward_dynamics": qdd_fd[p],
            "coriolis_matrix": C[ix],
            "end_effector_pose": T,
            "qd": np.asarray(s["qd"]),
        }


def rel_err(x, y):
    """(max |x - y| / max(||y||_inf, tiny), within tolerance?)"""
    x, y = np.asarray(x, float), np.asarray(y, float)
    diff = np.max(np.abs(x - y)) if x.size else 0.0
    ny = np.max(np.abs(y)) if y.size else 0.0
    ok = x.shape == y.shape and diff <= REL * ny + ABS
    return diff / max(ny, 1e-300), bool(ok)


def random_states(n, count, rng):
    out = []
    for _ in range(count):
        out.append({
            "q": rng.uniform(-np.pi, np.pi, n).tolist(),
            "qd": rng.uniform(-2.0, 2.0, n).tolist(),
            "qdd": rng.uniform(-3.0, 3.0, n).tolist(),
            "tau": rng.uniform(-20.0, 20.0, n).tolist(),
        })
    return out


def compare(ours_list, refs, keys):
    """Per key: (max relative error, all within tolerance?)."""
    out = {}
    for k in keys:
        errs = [rel_err(o[k], r[k]) for o, r in zip(ours_list, refs)]
        out[k] = (max(e for e, _ in errs), all(ok for _, ok in errs))
    return out


def coriolis_matrix_report(ours_list, refs):
    agree = compare(ours_list, refs, ["coriolis_matrix"])["coriolis_matrix"]
    ours_cqd = [rel_err(np.asarray(o["coriolis_matrix"]) @ r["qd"], r["coriolis"]) for o, r in zip(ours_list, refs)]
    pin_cqd = [rel_err(r["coriolis_matrix"] @ r["qd"], r["coriolis"]) for r in refs]
    return {
        "C_ours_vs_pin": agree,
        "C_ours_qd_eq_c": (max(e for e, _ in ours_cqd), all(ok for _, ok in ours_cqd)),
        "C_pin_qd_eq_c": (max(e for e, _ in pin_cqd), all(ok for _, ok in pin_cqd)),
    }


# ---------------------------------------------------------------- the scratch crate

CARGO_TOML = """[package]
name = "vendor-check"
version = "0.0.0"
edition = "2021"
publish = false

[workspace]

[dependencies]
nalgebra = "0.35"

[build-dependencies]
dynamics-gen = {{ path = "{gen}" }}
"""

BUILD_RS_HEAD = """// Generated by tools/vendor_check/check.py.
use dynamics_gen::Builder;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
"""

MAIN_RS_HEAD = """// Generated by tools/vendor_check/check.py: reads one robot name per argv and states as lines
// `q.. qd.. qdd.. tau..` (whitespace-separated, 4n numbers); prints one JSON line per state.
use std::io::BufRead;
"""

MAIN_RS_EVAL = """
fn vec_json(v: &[f64]) -> String {
    let items: Vec<String> = v.iter().map(|x| format!("{x:?}")).collect();
    format!("[{}]", items.join(","))
}

macro_rules! eval_robot {
    ($ty:ty, $line:expr) => {{
        const N: usize = <$ty>::DOF;
        let x: Vec<f64> = $line.split_whitespace().map(|t| t.parse().expect("a number")).collect();
        assert_eq!(x.len(), 4 * N, "expected 4n numbers");
        let v = |k: usize| nalgebra::SVector::<f64, N>::from_column_slice(&x[k * N..(k + 1) * N]);
        let (q, qd, qdd, tau) = (v(0), v(1), v(2), v(3));
        let r = <$ty>::default();
        let m = r.mass_matrix(&q);
        let rows: Vec<String> = (0..N).map(|i| vec_json(m.row(i).transpose().as_slice())).collect();
        format!(
            "{{\\"joint_names\\":[{}],\\"mass_matrix\\":[{}],\\"coriolis\\":{},\\"gravity\\":{},\\"inverse_dynamics\\":{},\\"forward_dynamics\\":{}}}",
            <$ty>::JOINT_NAMES.iter().map(|n| format!("{n:?}")).collect::<Vec<_>>().join(","),
            rows.join(","),
            vec_json(r.coriolis(&q, &qd).as_slice()),
            vec_json(r.gravity(&q).as_slice()),
            vec_json(r.inverse_dynamics(&q, &qd, &qdd).as_slice()),
            vec_json(r.forward_dynamics(&q, &qd, &tau).as_slice()),
        )
    }};
}

fn main() {
    let robot = std::env::args().nth(1).expect("robot name");
    for line in std::io::stdin().lock().lines() {
        let line = line.expect("stdin");
        if line.trim().is_empty() {
            continue;
        }
        let out = match robot.as_str() {
"""


def ident(stem):
    s = "".join(c if c.isalnum() else "_" for c in stem).lower()
    return "r_" + s


def camel(stem):
    return "R" + "".join(w.capitalize() for w in "".join(c if c.isalnum() else " " for c in stem).split())


CARGO_TOML_DERIVE = """[package]
name = "vendor-check-derive"
version = "0.0.0"
edition = "2021"
publish = false

[workspace]

[dependencies]
nalgebra = "0.35"
dynamics-macros = {{ path = "{macros}" }}
"""


def write_files(crate, files):
    """Writes each file only when its text changed (so cargo rebuilds only what changed)."""
    for name, text in files.items():
        p = os.path.join(crate, name)
        old = open(p).read() if os.path.exists(p) else None
        if old != text:
            with open(p, "w") as f:
                f.write(text)


def write_derive_crate(crate, macros_path, robots):
    """The same scratch crate, with `#[derive(Dynamics)]` instead of build.rs."""
    os.makedirs(os.path.join(crate, "src"), exist_ok=True)
    mods, arms = [], []
    for r in robots:
        key = r["key"]
        opts = [f"file = {json.dumps(r['path'])}"]
        if r.get("tip"):
            opts.append(f"tip = {json.dumps(r['tip'])}")
        if r.get("lock"):
            opts.append("lock(" + ", ".join(f"{j} = {float(v)!r}" for j, v in r["lock"].items()) + ")")
        mods.append(f"#[derive(Default, dynamics_macros::Dynamics)]\n#[dynamics({', '.join(opts)})]\npub struct {camel(key)};\n")
        arms.append(f'            "{key}" => eval_robot!({camel(key)}, line),\n')
    files = {
        "Cargo.toml": CARGO_TOML_DERIVE.format(macros=macros_path),
        "src/main.rs": (MAIN_RS_HEAD + "".join(mods) + MAIN_RS_EVAL + "".join(arms)
                        + '            other => panic!("unknown robot {other}"),\n        };\n        println!("{out}");\n    }\n}\n'),
    }
    write_files(crate, files)


def write_crate(crate, gen_path, robots):
    os.makedirs(os.path.join(crate, "src"), exist_ok=True)
    files = {"Cargo.toml": CARGO_TOML.format(gen=gen_path)}
    b = [BUILD_RS_HEAD]
    mods, arms = [], []
    for r in robots:
        key = r["key"]
        calls = f'    Builder::new({json.dumps(r["path"])})\n        .name("{camel(key)}")\n        .out_file("{ident(key)}.rs")\n'
        if r.get("tip"):
            calls += f'        .tip({json.dumps(r["tip"])})\n'
        for j, v in r.get("lock", {}).items():
            calls += f"        .lock({json.dumps(j)}, {float(v)!r})\n"
        calls += '        .compile()\n        .unwrap_or_else(|e| panic!("dynamics-gen: {e}"));\n'
        b.append(calls)
        mods.append(f'mod {ident(key)} {{\n    include!(concat!(env!("OUT_DIR"), "/{ident(key)}.rs"));\n}}\n')
        arms.append(f'            "{key}" => eval_robot!({ident(key)}::{camel(key)}, line),\n')
    b.append("}\n")
    files["build.rs"] = "".join(b)
    files["src/main.rs"] = (MAIN_RS_HEAD + "".join(mods) + MAIN_RS_EVAL + "".join(arms)
                            + '            other => panic!("unknown robot {other}"),\n        };\n        println!("{out}");\n    }\n}\n')
    write_files(crate, files)


def cargo_build(crate, target_dir, jobs):
    env = dict(os.environ, CARGO_TARGET_DIR=target_dir, CARGO_BUILD_JOBS=str(jobs))
    t0 = time.perf_counter()
    p = subprocess.run(["cargo", "build", "--release", "--quiet"], cwd=crate, env=env, capture_output=True, text=True)
    dt = time.perf_counter() - t0
    if p.returncode != 0:
        sys.exit(f"cargo build of {crate} failed:\n{p.stderr[-5000:]}")
    return dt


# ---------------------------------------------------------------- main


def fmt(e):
    err, ok = e
    return f"{err:.1e}{'' if ok else ' FAIL'}"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--config", default=os.path.join(os.path.dirname(__file__), "arms.json"))
    ap.add_argument("--urdf-dir", default=None, help="base of the config's relative paths (default: example-robot-data's robots/)")
    ap.add_argument("--repo", default=os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..")))
    ap.add_argument("--states", type=int, default=20)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--crate", default="/tmp/vendor-check", help="scratch crate directory (outside the repo)")
    ap.add_argument("--target-dir", default="/tmp/vendor-target")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--no-generated", action="store_true", help="skip step 3 (the generated code)")
    ap.add_argument("--front", choices=["builder", "derive"], default="builder",
                    help="step 3 through build.rs and the Builder, or through #[derive(Dynamics)]")
    ap.add_argument("--clean", action="store_true", help="time a clean build of the scratch crate (rm -rf the target dir first)")
    ap.add_argument("--json", default=None, help="write the full results here")
    args = ap.parse_args()

    urdf_dir = args.urdf_dir or default_urdf_dir()
    exe = os.path.join(args.repo, "target", "release", "dynamics-gen")
    if not os.path.exists(exe):
        sys.exit(f"{exe} not found: run `cargo build --release -p dynamics-gen` in {args.repo}")
    robots = json.load(open(args.config))
    rng = np.random.default_rng(args.seed)
    results, usable = [], []
    for r in robots:
        r["path"] = os.path.abspath(os.path.join(urdf_dir or ".", r["file"]))
        r["key"] = r.get("key") or os.path.splitext(os.path.basename(r["file"]))[0]
        res = {"robot": r["key"], "file": r["file"], "tip": r.get("tip"), "locks": len(r.get("lock", {}))}
        results.append(res)
        opts = cli_options(r)
        p, _ = run([exe, "joints", r["path"], *opts])
        if p.returncode != 0:
            res["error"] = p.stderr.strip()
            print(f"== {r['key']}: dynamics-gen joints failed:\n{p.stderr.strip()}\n")
            continue
        names = [line.split()[0] for line in p.stdout.splitlines() if line.strip()]
        res["dof"], res["joints"] = len(names), names
        tip = tip_link(r["path"], names, r.get("tip"))
        res["tip_link"] = tip
        model = PinRobot(r["path"], names, r.get("lock", {}), tip)
        res["continuous"] = sum(model.continuous)
        states = random_states(len(names), args.states, rng)
        refs = [model.evaluate(s) for s in states]
        p, dt_eval = run([exe, "eval", r["path"], *opts], "".join(json.dumps(s) + "\n" for s in states))
        if p.returncode != 0:
            res["error"] = p.stderr.strip()
            print(f"== {r['key']}: dynamics-gen eval failed:\n{p.stderr.strip()}\n")
            continue
        ours = [json.loads(line) for line in p.stdout.splitlines()]
        res["eval"] = compare(ours, refs, QUANTITIES + ["end_effector_pose"])
        res["coriolis_matrix"] = coriolis_matrix_report(ours, refs)
        out = os.path.join(args.crate, "generated", r["key"] + ".rs")
        os.makedirs(os.path.dirname(out), exist_ok=True)
        p, dt_gen = run([exe, "generate", r["path"], *opts, "-o", out])
        res["generate_s"] = dt_gen
        res["generated_lines"] = sum(1 for _ in open(out)) if p.returncode == 0 else None
        r["states"], r["refs"] = states, refs
        usable.append(r)

    if not args.no_generated and usable:
        if args.clean and os.path.isdir(args.target_dir):
            shutil.rmtree(args.target_dir)
        if args.front == "derive":
            write_derive_crate(args.crate, os.path.join(args.repo, "dynamics-macros"), usable)
        else:
            write_crate(args.crate, os.path.join(args.repo, "dynamics-gen"), usable)
        t_first = cargo_build(args.crate, args.target_dir, args.jobs)
        os.utime(usable[0]["path"])  # touch one robot file: the crate regenerates and recompiles
        t_touch = cargo_build(args.crate, args.target_dir, args.jobs)
        bin_name = "vendor-check-derive" if args.front == "derive" else "vendor-check"
        bin_path = os.path.join(args.target_dir, "release", bin_name)
        for r, res in zip(usable, [x for x in results if "eval" in x]):
            n = len(r["states"][0]["q"])
            lines = "".join(" ".join(repr(float(v)) for k in ("q", "qd", "qdd", "tau") for v in s[k]) + "\n" for s in r["states"])
            p, _ = run([bin_path, r["key"]], lines)
            if p.returncode != 0:
                res["generated"] = {"error": p.stderr.strip()}
                continue
            ours = [json.loads(line) for line in p.stdout.splitlines()]
            assert len(ours) == len(r["states"]) and all(len(o["coriolis"]) == n for o in ours)
            if ours[0]["joint_names"] != res["joints"]:
                res["generated"] = {"error": f"JOINT_NAMES {ours[0]['joint_names']} differ from `joints` {res['joints']}"}
                continue
            res["generated"] = compare(ours, r["refs"], QUANTITIES)
        build = {"first_build_s": t_first, "clean": args.clean, "after_touch_s": t_touch, "touched": usable[0]["key"]}
    else:
        build = None

    # ---------------- report
    short = {"mass_matrix": "M", "coriolis": "c", "gravity": "g", "inverse_dynamics": "ID", "forward_dynamics": "FD", "end_effector_pose": "T_ee"}
    print(f"max relative error max|x-y|/||y||_inf over {args.states} states (FAIL: beyond 1e-9 ||y|| + 1e-12)\n")
    head = ["robot", "DOF", "cont", "locks", "src"] + [short[q] for q in QUANTITIES] + ["T_ee", "C=C_pin", "C qd=c", "C_pin qd=c"]
    rows = []
    for res in results:
        if "eval" not in res:
            rows.append([res["robot"], "-", "-", str(res["locks"]), "ERROR"] + [""] * (len(head) - 5))
            continue
        e, cm = res["eval"], res["coriolis_matrix"]
        base = [res["robot"], str(res["dof"]), str(res["continuous"]), str(res["locks"])]
        rows.append(base + ["eval"] + [fmt(e[q]) for q in QUANTITIES] + [fmt(e["end_effector_pose"])]
                    + [fmt(cm["C_ours_vs_pin"]), fmt(cm["C_ours_qd_eq_c"]), fmt(cm["C_pin_qd_eq_c"])])
        g = res.get("generated")
        if g and "error" not in g:
            rows.append(["", "", "", "", "gen"] + [fmt(g[q]) for q in QUANTITIES] + ["", "", "", ""])
        elif g:
            rows.append(["", "", "", "", "gen ERROR: " + g["error"][:60]] + [""] * (len(head) - 5))
    widths = [max(len(x[i]) for x in rows + [head]) for i in range(len(head))]
    for row in [head] + rows:
        print("  ".join(c.ljust(w) for c, w in zip(row, widths)).rstrip())
    print("\nrobot              generate (s)  generated lines")
    for res in results:
        if "generate_s" in res:
            print(f"{res['robot']:<18} {res['generate_s']:>12.3f}  {res['generated_lines']:>15}")
    if build:
        kind = "clean" if build["clean"] else "first (maybe incremental)"
        print(f"\nscratch crate release build: {kind} {build['first_build_s']:.1f} s; after touching {build['touched']}: {build['after_touch_s']:.1f} s")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"results": results, "build": build}, f, indent=1, default=str)
    bad = any("error" in r for r in results) or any(
        not ok for r in results for k, (e, ok) in list(r.get("eval", {}).items()) + list(r.get("generated", {}).items() if isinstance(r.get("generated"), dict) and "error" not in r["generated"] else []))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
