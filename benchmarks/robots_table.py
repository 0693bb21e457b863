"""Every robot of example-robot-data through symdyn: generate, compile, verify; one table.

For each URDF of the example-robot-data wheel that Pinocchio's parser reads (with its mimic
joints where the file has them), as the file is (no editing): ``symdyn generate`` of the default
functions (no cache; on a floating base where the robot is mobile: legged, humanoid, flying or on
wheels), ``gcc -std=c99 -O2 -c`` of the C file (of each, where the C is in several files: the times
summed, the largest peak), and ``symdyn verify`` against Pinocchio's reading
of the file. Wall time and peak memory (``/usr/bin/time``'s maximum resident set) of the generation
and the compilation, and verify's worst normalized error and what it skipped, as a Markdown
table on standard output (docs/benchmarks.md, "Every robot of example-robot-data").

    python benchmarks/robots_table.py [--jobs 2] [--only NAME,...] [--states 20]
"""

from __future__ import annotations

import argparse
import concurrent.futures
import os
import re
import subprocess
import sys
import sysconfig
import tempfile

ROOT = os.path.join(sysconfig.get_paths()["purelib"], "cmeel.prefix", "share", "example-robot-data", "robots")
#: the robots that move freely (legged, humanoid, flying, on wheels): read on a floating base
MOBILE = ("a1", "alex", "alexander", "anymal", "b1", "bolt", "borinot", "centauro", "g1", "go1", "go2", "quadrotor",
          "hextilt", "human", "hyq", "icub", "iris", "laikago", "quadruped", "romeo", "simple_humanoid", "solo",
          "talos_full", "talos_reduced", "tiago")


def urdfs() -> list[str]:
    found = []
    for directory, _, files in os.walk(ROOT):
        found += [os.path.join(directory, f) for f in files if f.endswith(".urdf")]
    return sorted(found, key=lambda p: os.path.basename(p))


def mobile(path: str) -> bool:
    name = os.path.basename(path)
    return any(name.startswith(m) for m in MOBILE) and "left_arm" not in name


def pinocchio_reads(path: str) -> str:
    """'' when Pinocchio's parser reads the file (mimic joints as mimics where it has them), else why not."""
    import pinocchio as pin
    with open(path, encoding="utf-8") as handle:
        mimic = "<mimic" in handle.read()
    try:
        pin.buildModelFromUrdf(path, mimic=mimic) if mimic else pin.buildModelFromUrdf(path)
        return ""
    except Exception as exc:  # noqa: BLE001 (reported in the table)
        if mimic:  # (Pinocchio 4.1 refuses some mimic trees, e.g. TALOS full v2: it reads them without)
            try:
                pin.buildModelFromUrdf(path)
                return ""
            except Exception:  # noqa: BLE001
                pass
        return f"{type(exc).__name__}: {str(exc).splitlines()[0][:80]}"


def timed(command: list[str], cwd: str) -> tuple[int, float, float, str]:
    """``(exit status, wall seconds, peak MB, output)`` of ``command`` under /usr/bin/time."""
    run = subprocess.run(["/usr/bin/time", "-f", "TIME %e %M", *command], cwd=cwd, capture_output=True, text=True)
    match = re.search(r"TIME ([0-9.]+) ([0-9]+)\s*$", run.stderr)
    seconds, peak = (float(match.group(1)), int(match.group(2)) / 1024) if match else (-1.0, -1.0)
    return run.returncode, seconds, peak, run.stdout + re.sub(r"TIME [0-9.]+ [0-9]+\s*$", "", run.stderr)


def one(path: str, states: int) -> dict:
    name = os.path.basename(path)[:-5]
    row = {"robot": name, "floating": mobile(path)}
    why = pinocchio_reads(path)
    if why:
        return {**row, "note": f"Pinocchio does not read it ({why})"}
    flags = ["--floating-base"] if row["floating"] else []
    symdyn = [sys.executable, "-m", "symdyn"]
    with tempfile.TemporaryDirectory(prefix="robots_table_") as work:
        status, row["generate_s"], row["generate_mb"], out = timed(
            [*symdyn, "generate", path, *flags, "--out", "out", "--no-cache"], work)
        if status != 0:
            return {**row, "note": "generate: " + out.strip().splitlines()[-1][:160]}
        header = next(f for f in os.listdir(os.path.join(work, "out")) if f.endswith("_dynamics.h"))
        with open(os.path.join(work, "out", header), encoding="utf-8") as handle:
            text = handle.read()
        row["joints"] = int(re.search(r"#define [A-Z0-9_]+_DOF ([0-9]+)", text).group(1)) - (6 if row["floating"] else 0)
        row["mimics"] = len(re.findall(r"mimic\.joint = ", text))
        sources = sorted((f for f in os.listdir(os.path.join(work, "out")) if f.endswith(".c")),
                         key=lambda f: (len(f), f))  # NAME_dynamics.c, then NAME_dynamics_2.c, ...
        row["c_kb"] = sum(os.path.getsize(os.path.join(work, "out", f)) for f in sources) / 1024
        row["c_files"] = len(sources)
        row["compile_s"], row["compile_mb"] = 0.0, 0.0
        for source in sources:  # each translation unit alone: times summed, the largest peak
            status, seconds, peak, out = timed(["gcc", "-std=c99", "-O2", "-c", os.path.join("out", source),
                                                "-o", "x.o"], work)
            if status != 0:
                return {**row, "note": "gcc: " + out.strip().splitlines()[-1][:160]}
            row["compile_s"] += seconds
            row["compile_mb"] = max(row["compile_mb"], peak)
        run = subprocess.run([*symdyn, "verify", path, *flags, "--states", str(states)], cwd=work,
                             capture_output=True, text=True)
        errors = [float(m.group(1)) for m in re.finditer(r"^\S+\s+([0-9.e+-]+)\s+(ok|FAIL)", run.stdout, re.M)]
        row["verify"] = max(errors) if errors else float("nan")
        row["verified"] = run.returncode == 0
        skipped = re.search(r"\(skipped ([a-z_, ]+):", run.stdout)
        row["note"] = f"skipped {skipped.group(1)} (singular M)" if skipped else ""
        if run.returncode != 0 and not errors:
            row["note"] = "verify: " + (run.stdout + run.stderr).strip().splitlines()[-1][:160]
    return row


def table(rows: list[dict]) -> str:
    out = ["| robot | base | joints (mimics) | generate | peak | C | gcc -O2 | peak | verify worst | note |",
           "|---|---|---:|---:|---:|---:|---:|---:|---:|---|"]
    for r in rows:
        if "joints" not in r:
            out.append(f"| {r['robot']} | {'floating' if r['floating'] else 'fixed'} | | | | | | | | {r['note']} |")
            continue
        mimics = f" ({r['mimics']})" if r["mimics"] else ""
        files = f" in {r['c_files']} files" if r.get("c_files", 1) > 1 else ""
        verify = (f"{r['verify']:.1e}" + ("" if r["verified"] else " FAIL")) if "verify" in r else ""
        compile_cells = (f"{r['compile_s']:.1f} s | {r['compile_mb']:.0f} MB" if "compile_s" in r else " | ")
        out.append(f"| {r['robot']} | {'floating' if r['floating'] else 'fixed'} | {r['joints']}{mimics} | "
                   f"{r['generate_s']:.1f} s | {r['generate_mb']:.0f} MB | {r['c_kb']:.0f} kB{files} | {compile_cells} | "
                   f"{verify} | {r.get('note', '')} |")
    return "\n".join(out)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--jobs", type=int, default=1, help="robots at once (each its own processes)")
    parser.add_argument("--only", default="", help="comma-separated file names (without .urdf)")
    parser.add_argument("--states", type=int, default=20, help="verify's random states")
    args = parser.parse_args(argv)
    paths = urdfs()
    if args.only:
        wanted = set(args.only.split(","))
        paths = [p for p in paths if os.path.basename(p)[:-5] in wanted]
    rows = {}
    with concurrent.futures.ProcessPoolExecutor(args.jobs) as pool:
        futures = {pool.submit(one, path, args.states): path for path in paths}
        for future in concurrent.futures.as_completed(futures):
            row = future.result()
            rows[futures[future]] = row
            print(f"{row['robot']}: {row}", file=sys.stderr, flush=True)  # (progress, and rows so far)
    names = [os.path.basename(path) for path in paths]
    rows = [dict(rows[path], robot=f"{rows[path]['robot']} ({os.path.relpath(path, ROOT).split(os.sep)[0]})")
            if names.count(os.path.basename(path)) > 1 else rows[path] for path in paths]  # (two anymal.urdf)
    print(table(rows))
    return 0 if all(r.get("verified", True) for r in rows) else 1


def table_from_log(path: str) -> str:
    """The table of the rows a run printed on standard error so far (an interrupted run)."""
    import ast
    with open(path, encoding="utf-8") as handle:
        rows = [ast.literal_eval(line.split(": ", 1)[1]) for line in handle if line.split(": ", 1)[0].strip()
                and line.rstrip().endswith("}")]
    return table(sorted(rows, key=lambda r: r["robot"]))


if __name__ == "__main__":
    sys.exit(main())
