#!/usr/bin/env python3
"""Write docs/urdf-compatibility.md: `dynamics-gen joints FILE` on every URDF of
example-robot-data, and, for the refused trees and mimic joints, once more with the locks the
error suggests (one round).

    python3 -m venv /tmp/pinvenv && /tmp/pinvenv/bin/pip install example-robot-data
    cargo build --release -p dynamics-gen
    /tmp/pinvenv/bin/python tools/urdf_table.py --bin target/release/dynamics-gen

No third-party file is copied; the table names files relative to the package's robots/.
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


def joints(binary, path, locks=()):
    cmd = [binary, "joints", path]
    for lock in locks:
        cmd += ["--lock", lock]
    p = subprocess.run(cmd, capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


def reason(first_line):
    """A short category for a refusal's first error line."""
    for key, name in [
        ("trees are not supported", "tree"),
        ("field `mimic`", "mimic joint"),
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
    m = re.sub(r" \(through .*\)", "", m)  # the branch lists are long
    m = m.replace("; trees are not supported yet, only serial chains", "")
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


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bin", default=os.path.join(REPO, "target", "release", "dynamics-gen"))
    ap.add_argument("--urdf-dir", default=default_urdf_dir())
    ap.add_argument("--out", default=os.path.join(REPO, "docs", "urdf-compatibility.md"))
    args = ap.parse_args()
    try:
        version = importlib.metadata.version("example-robot-data")
    except importlib.metadata.PackageNotFoundError:
        version = "unknown"
    files = sorted(glob.glob(os.path.join(args.urdf_dir, "**", "*.urdf"), recursive=True))
    rows, counts, locked = [], collections.Counter(), collections.Counter()
    still = collections.Counter()
    for path in files:
        rel = os.path.relpath(path, args.urdf_dir)
        rc, out, err = joints(args.bin, path)
        if rc == 0:
            counts["loads"] += 1
            rows.append((rel, f"loads ({len(out.splitlines())} joints)", "", ""))
            continue
        first = err.splitlines()[0] if err else "(no message)"
        why = reason(first)
        counts[why] += 1
        retry, desc = "", short(first, path)
        if why == "tree":
            points = sum("trees are not supported" in line for line in err.splitlines())
            desc += f" ({points} branch point{'s' * (points > 1)} reported)"
        if why in ("tree", "mimic joint"):
            locks = suggested_locks(err)
            rc2, out2, err2 = joints(args.bin, path, locks)
            if rc2 == 0:
                locked[why] += 1
                retry = f"loads ({len(out2.splitlines())} joints) with {len(locks)} locks"
            else:
                line = err2.splitlines()[0]
                still[field(line)] += 1
                retry = "still refused: " + short(line, path, 90)
        rows.append((rel, f"refused: {why}", desc, retry))
    total = len(files)
    summary = [f"- {total} files: {counts['loads']} load, {total - counts['loads']} refused"]
    for why in ["tree", "mimic joint", "no movable joint", "no links", "other"]:
        if counts[why]:
            extra = ""
            if why in ("tree", "mimic joint"):
                extra = f" ({locked[why]} of them load with the suggested locks, one round)"
            summary.append(f"  - {why}: {counts[why]}{extra}")
    for f, k in still.items():
        summary.append(f"  - with the suggested locks, still refused on field `{f}`: {k}")
    lines = [
        "# URDF compatibility: example-robot-data",
        "",
        f"`dynamics-gen joints FILE` on every `.urdf` of the PyPI package example-robot-data "
        f"{version} (its `share/example-robot-data/robots/` directory), made by "
        "`tools/urdf_table.py` (re-run it to refresh this page; no URDF is copied into this repo).",
        "For the trees and mimic joints, the last column runs the same command again with the locks "
        "the error suggests (`--lock` of every error line, once).",
        "",
        "Trees (legged robots, humanoids, hands) are refused with \"trees are not supported yet\" "
        "and lock suggestions. "
        + (
            "No file is refused because of visual, collision or extension elements: every "
            "refusal is about the kinematic structure."
            if counts["other"] == 0
            else f"{counts['other']} files are refused for other reasons (see the table)."
        ),
        "",
        *summary,
        "",
        "A refusal with the suggested locks is the loader's physical check of each link's "
        "inertia on the kept chain (triangle inequality, positive semidefinite, no rotational "
        "inertia without mass), which Pinocchio does not make: the locks themselves were "
        "accepted and left one serial chain.",
        "",
        "| file (in `robots/`) | result | why (first error line, shortened) | with the suggested locks |",
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
