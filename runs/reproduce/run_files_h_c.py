"""Every shipped run file that claims a scallop limit: its best plan cut on three grids.

    python runs/reproduce/run_files_h_c.py [--files runs/X.yaml ...] [--set KEY=VALUE ...]
                                           [--out PATH | --regenerate]
    python runs/reproduce/run_files_h_c.py --check    # the record still the engine's plans?

A run file claims the limit h_c when its passes are spaced for it: a ``toolpath`` run
with ``spacing: scallop`` (an ``evoplan run`` file, optimized as the file says), or an
``evoplan zone`` file (its one plan). Stepover-spaced files with an ``h_c`` (the scallop
is then a criterion, not a limit) are listed as not claiming it. For each claim the best
plan (``best.json`` of the run, the zone file's plan) is simulated on the 0.2, 0.1 and
0.05 mm grids and judged by ``simulation.metrics.meets_h_c`` (p99 < h_c, max <= 1.1 h_c,
nothing uncut, gouge within the chord tolerance); a verdict that changes between 0.1 and
0.05 mm is flagged. ``--set`` changes every run's settings (e.g. a small budget:
``--set termination.generations=1``: then the report says so and is not the committed one).

Writes the report to ``--out`` (default ``results/reproduce/run_files_h_c.md``) and beside
it ``run_files_h_c.json``: per file its sha256, the best decisions and lengths, the
verdicts (what ``tests/problems/toolpath/test_run_files_h_c.py`` reads: a run file edited
since its verdict was recorded fails it, a recorded verdict that does not meet h_c is an
expected failure naming why). ``--check`` re-plans the committed record's best decisions
(no run, no cut) and exits 1 when a papers' length moved: the engine changed since the
record, regenerate it.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from outputs import add_report_options, resolve_report_paths  # runs/reproduce/outputs.py

ROOT = Path(__file__).resolve().parents[2]


def claim(path: Path) -> tuple[str, float | None, str]:
    """(kind, h_c, why) of a run file: kind ``run`` / ``zone`` (claims h_c) or ``none``."""
    from evoplan.safe_yaml import load_file

    data = load_file(path)
    if not isinstance(data, dict):
        return "none", None, "not a mapping"
    if "problem" not in data and "cutter" in data and "h_c" in data:
        return "zone", float(data["h_c"]), "an evoplan zone file: its plan is spaced for h_c"
    problem = data.get("problem")
    if not isinstance(problem, dict) or problem.get("name") != "toolpath":
        studies = [p for p in data.get("problems") or [] if isinstance(p, dict)
                   and p.get("name") == "toolpath"]
        if any((p.get("params") or {}).get("spacing") == "scallop" for p in studies):
            return "none", None, "a study: its reproduction script simulates its best plans"
        if studies:
            return "none", None, "a study of stepover-spaced toolpath problems (no limit)"
        return "none", None, "no toolpath problem"
    params = problem.get("params") or {}
    if params.get("spacing") != "scallop":
        why = ("stepover spacing: h_c is a criterion, not a limit" if "h_c" in params
               else "no h_c")
        return "none", None, why
    return "run", float(params.get("h_c", 0.254)), "passes spaced for h_c"


def sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def best_of_run(path: Path, sets: list[str], work: Path):
    """(problem, decisions, criteria) of the best plan of ``evoplan run FILE``."""
    from evoplan.cli import main as cli_main
    from evoplan.config import parse_config
    from evoplan.run_folder import read_run_folder
    from evoplan.runner import prepare

    out = work / path.stem
    argv = ["run", str(path), "--out", str(out), "--quiet"]
    for s in sets:
        argv += ["--set", s]
    if cli_main(argv) != 0:
        raise SystemExit(f"{path}: the run failed")
    folder = read_run_folder(str(out), False)
    data = dict(folder.config)
    data.setdefault("name", out.name)
    problem = prepare(parse_config(data, str(folder.config_path)),
                      str(folder.config_path)).evaluator.problem
    params = folder.best["variables"]
    crit = problem.criteria(problem.row(params))
    return problem, params, {k: float(v[0]) for k, v in crit.items()}


def zone_plan(path: Path):
    """(planner, genes, summary) of an ``evoplan zone`` file's plan."""
    from evoplan.commands.zone import build_plan, load, summary

    cfg = load(str(path))
    surface, planner, genes, batch, seconds = build_plan(cfg, path.parent)
    return planner, genes, summary(cfg, planner, genes, batch, seconds)


def judge(surface, path, h_c: float, tolerance: float, allowance: float = 0.5) -> dict:
    from evoplan.problems.toolpath.simulation import design_grid, simulate
    from evoplan.problems.toolpath.simulation.metrics import VERDICT_GRIDS_MM, verdicts

    sims = {}
    for h in VERDICT_GRIDS_MM:
        sims[h] = simulate(path, design_grid(surface, h), allowance=allowance).metrics
    v = verdicts(sims, h_c, tolerance)
    return {"grids": {str(h): {"max": sims[h]["scallop_max_mm"],
                               "p99": sims[h]["scallop_p99_mm"],
                               "uncut": sims[h]["uncut_fraction"],
                               "gouge": sims[h]["gouge_max_mm"],
                               "meets": bool(v["by_grid"][h][0]),
                               "why": list(v["by_grid"][h][1])} for h in VERDICT_GRIDS_MM},
            "meets": bool(v["final"]), "flip": bool(v["flip"])}


def check_file(path: Path, sets: list[str], work: Path) -> dict:
    kind, h_c, why = claim(path)
    rec = {"file": str(path.relative_to(ROOT)), "sha256": sha256(path), "claims_h_c": kind != "none",
           "kind": kind, "why": why, "h_c": h_c}
    if kind == "none":
        return rec
    t0 = time.perf_counter()
    if kind == "run":
        problem, params, crit = best_of_run(path, sets, work)
        cl, _ = problem.cl_path(params)
        surface, tol = problem.surface, problem.tolerance
        rec.update(best={k: (v if isinstance(v, (int, str)) else float(v))
                         for k, v in params.items()},
                   zones=int(crit.get("zones", 1)),
                   length_papers_mm=crit.get("length_papers_mm"),
                   eq4_total=crit.get("eq4_total"), cc_count=int(crit["cc_count"]))
    else:
        planner, genes, s = zone_plan(path)
        cl = planner.cl_path(genes)
        surface, tol = planner.surface, planner.tolerance
        rec.update(best={"strategy": s.get("strategy"), "method": s.get("method")},
                   zones=int(s["n_zones"]), length_papers_mm=s["length_papers_mm"],
                   eq4_total=s.get("total_length_mm"), cc_count=int(s.get("cc_points", 0)))
    rec.update(judge(surface, cl, h_c, tol))
    rec["seconds"] = round(time.perf_counter() - t0, 1)
    return rec


def replan_length(path: Path, rec: dict) -> float:
    """The papers' length the engine makes today of a record's best decisions."""
    if rec["kind"] == "zone":
        return float(zone_plan(path)[2]["length_papers_mm"])
    from evoplan.config import parse_config
    from evoplan.runner import prepare
    from evoplan.safe_yaml import load_file

    problem = prepare(parse_config(load_file(path), str(path)), str(path)).evaluator.problem
    return float(problem.criteria(problem.row(rec["best"]))["length_papers_mm"][0])


def check(record_path: Path) -> int:
    stale = 0
    for rec in json.loads(record_path.read_text())["records"]:
        if not rec["claims_h_c"]:
            continue
        now = replan_length(ROOT / rec["file"], rec)
        same = abs(now - rec["length_papers_mm"]) <= 1e-6 * rec["length_papers_mm"]
        stale += not same
        print(f"{rec['file']}: recorded {rec['length_papers_mm']:.3f} mm, today {now:.3f} mm"
              f"{'' if same else '  STALE'}", flush=True)
    return 1 if stale else 0


def report(records: list[dict], sets: list[str]) -> str:
    from evoplan.problems.toolpath.simulation.metrics import VERDICT_GRIDS_MM

    head = ("| run file | best plan | zones | papers (mm) | "
            + " | ".join(f"max / p99 @{h}" for h in VERDICT_GRIDS_MM)
            + " | meets h_c @" + " / ".join(str(h) for h in VERDICT_GRIDS_MM) + " | why not @0.05 |")
    lines = [head, "|" + "---|" * (head.count("|") - 1)]
    for r in records:
        if not r["claims_h_c"]:
            continue
        g = r["grids"]
        best = ", ".join(f"{k} {v:.3g}" if isinstance(v, float) else f"{k} {v}"
                         for k, v in r["best"].items())
        sim = " | ".join(f"{g[str(h)]['max']:.3f} / {g[str(h)]['p99']:.3f}" for h in VERDICT_GRIDS_MM)
        ok = " / ".join("yes" if g[str(h)]["meets"] else "no" for h in VERDICT_GRIDS_MM)
        lines.append(f"| `{r['file']}` | {best} | {r['zones']} | {r['length_papers_mm']:.1f} | {sim} | "
                     f"{ok}{' **FLIP**' if r['flip'] else ''} | {'; '.join(g['0.05']['why']) or '-'} |")
    rest = [f"- `{r['file']}`: {r['why']}" for r in records if not r["claims_h_c"]]
    how = f" with `{' '.join('--set ' + s for s in sets)}`" if sets else ""
    return ("# Shipped run files that claim a scallop limit: their best plans on three grids\n\n"
            f"Generated by `runs/reproduce/run_files_h_c.py`{how}. Each run as its file says; the "
            "best plan simulated on 0.2, 0.1 and 0.05 mm grids (meets h_c: p99 < h_c, max <= 1.1 "
            "h_c, nothing uncut, gouge within the chord tolerance).\n\n" + "\n".join(lines)
            + "\n\nNot claiming h_c:\n\n" + "\n".join(rest) + "\n")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--files", nargs="*", default=None, help="run files (default: runs/*.yaml)")
    ap.add_argument("--set", dest="sets", action="append", default=[],
                    help="KEY.PATH=VALUE for every run (a smaller budget)")
    ap.add_argument("--check", action="store_true",
                    help="re-plan the committed record's best decisions; exit 1 if one moved")
    add_report_options(ap)
    args = ap.parse_args(argv)
    if args.check:
        return check(Path(__file__).resolve().with_suffix(".json"))
    resolve_report_paths(args, __file__)
    if args.regenerate and args.sets:
        ap.error("--regenerate records the run files as they are: no --set")
    files = [Path(f).resolve() for f in args.files] if args.files else sorted((ROOT / "runs").glob("*.yaml"))
    with tempfile.TemporaryDirectory(prefix="run_files_h_c-") as work:
        records = []
        for f in files:
            rec = check_file(f, args.sets, Path(work))
            records.append(rec)
            if rec["claims_h_c"]:
                print(f"{rec['file']}: best {rec['best']}, papers {rec['length_papers_mm']:.1f} mm, "
                      f"0.05 max {rec['grids']['0.05']['max']:.3f} p99 {rec['grids']['0.05']['p99']:.3f} "
                      f"meets {rec['meets']}{' FLIP' if rec['flip'] else ''} ({rec['seconds']} s)",
                      flush=True)
    out = Path(args.out)
    out.write_text(report(records, args.sets))
    out.with_suffix(".json").write_text(json.dumps({"sets": args.sets, "records": records}, indent=1) + "\n")
    print(f"wrote {out} and {out.with_suffix('.json')}")
    return 0 if all(r["meets"] for r in records if r["claims_h_c"]) else 1


if __name__ == "__main__":
    sys.exit(main())
