#!/usr/bin/env python3
"""Write docs/urdf-compatibility.md: `dynamics-gen joints FILE` on every URDF of
example-robot-data; for the files that load, once more with `--floating-base`; for the
refused mimic joints (impossible couplings), once more with the locks the error suggests
(one round). Movable mimic joints load as coupled coordinates.

    python3 -m venv /tmp/pinvenv && /tmp/pinvenv/bin/pip install example-robot-data
    cargo build --release -p dynamics-gen
    /tmp/pinvenv/bin/python tools/urdf_table.py --bin target/release/dynamics-gen

(`--urdf-dir DIR/cmeel.prefix/share/example-robot-data/robots` reads an unpacked wheel
instead.) No third-party file is copied; the table names files relative to the package's
robots/.
"""

import argparse
import collections
import glob
import importlib.metadata
import os
import re
import site
import subprocess

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)


def default_urdf_dir():
    for sp in site.getsitepackages():
        d = os.path.join(sp, "cmeel.prefix", "share", "example-robot-data", "robots")
        if os.path.isdir(d):
            return d
    return None


def joints(binary, path, locks=(), floating=False):
    cmd = [binary, "joints", path]
    for lock in locks:
        cmd += ["--lock", lock]
    if floating:
        cmd.append("--floating-base")
    p = subprocess.run(cmd, capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


def reason(first_line):
    """A short category for a refusal's first error line."""
    for key, name in [
        ("field `mimic`", "mimic joint"),
        ("field `inertial.inertia`", "inertia"),
        ("field `inertia`: the mass matrix is singular", "singular mass matrix"),
        ("no movable joint", "no movable joint"),
        ("has no links", "no links"),
    ]:
        if key in first_line:
            return name
    return "other"


def short(first_line, path, n=110):
    """The first error line without `error: `, the file name and the fix, cut at `n`."""
    m = first_line.removeprefix("error: ").replace(path + ": ", "").replace(path, "FILE")
    m = m.split("; fix:")[0]
    return m if len(m) <= n else m[: n - 3] + "..."


def field(line):
    """The `field` an error line names."""
    found = re.search(r"field `([^`]*)`", line)
    return found.group(1) if found else "other"


def suggested_locks(stderr):
    """The last `--lock A=v,B=w` of every error line, each joint once (first wins)."""
    out = collections.OrderedDict()
    for line in stderr.splitlines():
        found = re.findall(r"--lock ([^\s`;,]+=[^\s`;,]+(?:,[^\s`;,]+=[^\s`;,]+)*)", line)
        if found:
            for pair in found[-1].split(","):
                name, value = pair.split("=", 1)
                if value != "VALUE":
                    out.setdefault(name, value)
    return [f"{n}={v}" for n, v in out.items()]


def loaded(out):
    """The joint coordinates, the mimic joints, whether a tree and whether on a floating base,
    of a `joints` listing (one line per movable joint; a mimic joint's says whom it follows)."""
    lines = [line for line in out.splitlines() if not line.startswith("(floating base)")]
    mimic = sum("  follows `" in line for line in lines)
    tree = any("hangs from" in line for line in lines)
    floating = any(line.startswith("(floating base)") for line in out.splitlines())
    return len(lines) - mimic, mimic, tree, floating


def describe(out):
    n, mimic, tree, floating = loaded(out)
    return (
        f"{n} joints"
        + (f" + {mimic} mimic" if mimic else "")
        + (", tree" if tree else "")
        + (", floating base" if floating else "")
    )


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bin", default=os.path.join(REPO, "target", "release", "dynamics-gen"))
    ap.add_argument("--urdf-dir", default=default_urdf_dir())
    ap.add_argument("--out", default=os.path.join(REPO, "docs", "urdf-compatibility.md"))
    args = ap.parse_args()
    try:
        version = importlib.metadata.version("example-robot-data")
    except importlib.metadata.PackageNotFoundError:
        # An unpacked wheel: <root>/cmeel.prefix/share/example-robot-data/robots beside
        # <root>/example_robot_data-VERSION.dist-info.
        root = os.path.join(args.urdf_dir, "..", "..", "..", "..")
        found = glob.glob(os.path.join(root, "example_robot_data-*.dist-info"))
        version = found[0].split("example_robot_data-")[-1][: -len(".dist-info")] if found else "unknown"
    files = sorted(glob.glob(os.path.join(args.urdf_dir, "**", "*.urdf"), recursive=True))
    rows, counts, locked = [], collections.Counter(), collections.Counter()
    still, kinds = collections.Counter(), collections.Counter()
    for path in files:
        rel = os.path.relpath(path, args.urdf_dir)
        rc, out, err = joints(args.bin, path)
        if rc == 0:
            counts["loads"] += 1
            _, mimic, tree, floating = loaded(out)
            kinds["tree"] += tree
            kinds["floating"] += floating
            kinds["mimic"] += mimic > 0
            if floating:
                fb = "floats already (floating root joint)"
            else:
                rc2, _, err2 = joints(args.bin, path, floating=True)
                if rc2 == 0:
                    kinds["floats"] += 1
                    fb = "loads"
                else:
                    line = err2.splitlines()[0]
                    still["--floating-base: " + field(line)] += 1
                    fb = "refused: " + short(line, path, 90)
            rows.append((rel, f"loads ({describe(out)})", "", fb))
            continue
        first = err.splitlines()[0] if err else "(no message)"
        why = reason(first)
        counts[why] += 1
        retry, desc = "", short(first, path)
        if why == "mimic joint":
            locks = suggested_locks(err)
            rc2, out2, err2 = joints(args.bin, path, locks)
            if rc2 == 0:
                locked[why] += 1
                retry = f"loads ({describe(out2)}) with {len(locks)} locks"
            else:
                line = err2.splitlines()[0]
                still[field(line)] += 1
                retry = "still refused: " + short(line, path, 90)
        rows.append((rel, f"refused: {why}", desc, retry))
    total = len(files)
    summary = [
        f"- {total} files: {counts['loads']} load, {total - counts['loads']} refused",
        f"  - of those that load: {kinds['tree']} trees, {kinds['floating']} on a floating root "
        f"joint; {kinds['floats']} of the others also load with `--floating-base`; "
        f"{kinds['mimic']} with mimic joints (coupled coordinates)",
    ]
    names = {
        "inertia": "physically impossible inertia (field `inertial.inertia`)",
        "singular mass matrix": "mass matrix singular for every q (joints that move no mass, field `inertia`)",
    }
    for why in ["mimic joint", "inertia", "singular mass matrix", "no movable joint", "no links", "other"]:
        if counts[why]:
            extra = ""
            if why == "mimic joint":
                extra = f" ({locked[why]} of them load with the suggested locks, one round)"
            summary.append(f"  - refused, {names.get(why, why)}: {counts[why]}{extra}")
    for f, k in still.items():
        if f.startswith("--floating-base: "):
            f = f.removeprefix("--floating-base: ")
            summary.append(f"  - loads, but refused with `--floating-base` on field `{f}`: {k}")
        else:
            summary.append(f"  - with the suggested locks, still refused on field `{f}`: {k}")
    lines = [
        "# URDF compatibility: example-robot-data",
        "",
        f"`dynamics-gen joints FILE` on every `.urdf` of the PyPI package example-robot-data "
        f"{version} (its `share/example-robot-data/robots/` directory), made by "
        "`tools/urdf_table.py` (re-run it to refresh this page; no URDF is copied into this repo).",
        "For the files that load, the last column runs it again with `--floating-base`; for the "
        "refused mimic joints, with the locks the error suggests (`--lock` of every error line, once). "
        "`N joints + M mimic`: N joint coordinates (the length of q without the base) and M mimic "
        "joints that follow one of them.",
        "",
        "Kinematic trees (legged robots, humanoids, hands) load whole, in Pinocchio's joint order; "
        "a URDF whose root joint is `floating` (a massless `world` link above the base) loads on a "
        "floating base, and `--floating-base` floats any other. "
        + (
            "No file is refused because of visual, collision or extension elements: every "
            "refusal is about the kinematic structure or the inertias."
            if counts["other"] == 0
            else f"{counts['other']} files are refused for other reasons (see the table)."
        ),
        "",
        *summary,
        "",
        "A refusal on `inertial.inertia` is the loader's physical check of each URDF link's "
        "inertia on a moving body (triangle inequality, positive semidefinite, no rotational "
        "inertia without mass), which Pinocchio does not make; on a fixed base the links welded "
        "to the base are not checked (they never move), with `--floating-base` they are. A "
        "movable `<mimic>` joint is a coupled coordinate (it moves its link as "
        "`multiplier·q_leader + offset` and has no entry of its own in q); only couplings that "
        "cannot be one are refused on field `mimic` (a leader the file does not have or that is "
        "fixed, a cycle, a zero multiplier), and locking the follower removes them.",
        "",
        "| file (in `robots/`) | result | why (first error line, shortened) | with `--floating-base`, or with the suggested locks |",
        "|---|---|---|---|",
    ]
    for rel, result, why, retry in rows:
        cell = lambda s: s.replace("|", "\\|")
        lines.append(f"| `{rel}` | {result} | {cell(why)} | {cell(retry)} |")
    os.makedirs(os.path.dirname(args.out), exist_ok=True)
    with open(args.out, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(summary))


if __name__ == "__main__":
    main()
