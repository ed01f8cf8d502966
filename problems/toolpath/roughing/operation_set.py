"""Every file of ``evoplan machine`` for one surface, built in memory from plain config data.

``build_operations(cfg, base_dir, plan)`` returns ({file name: bytes}, summary); any bad value
raises a one-line ValueError starting with its key path (``roughing.max_depth: ...``,
``post.dialect: ...``, ``post.kinematics: finish: point 12: ...``, ``stock.top: ...``).

``cfg`` is a machine file already validated by ``evoplan/commands/machine_config.py``
(``MachineConfig(...).model_dump()``): the post's dialect, a 5-axis post's kinematics and the
``finish.problem`` keys are checked there, once. What needs built objects is checked here: the
clearance plane against the stock top (computed from the surface), a 3-axis post refusing a
5-axis finish plan (``--from-run``'s plan included), the sizes, and what the operations and
posts find (an unreachable point, a depth above the stock).
"""

from __future__ import annotations

import json

import numpy as np

from ..criteria.kinematic_time import Dynamics, moves_time
from ..export.apt_write import apt_toolpath
from ..export.exchange import surface_dxf, surface_stl, toolpaths_dxf
from ..export.kinematics import Kinematics, ReachError
from ..export.posts import POSTS, Machine, PostError
from ..export.safety import check_program
from ..export.toolpath import Tool
from ..cutters import make_cutter
from ..geometry.spec import parse_surface
from .budget import check_sizes
from .figures import layers_png
from .operations import ball_on_offset, block_stock, finish_from_plan, roughing, surface_z_range


def _tool(c: dict, kind: str = "flat") -> Tool:
    """The NC tool of a roughing / semi-finish / finish entry: a flat end mill, or the ball
    of its diameter (``kind="ball"``)."""
    return Tool(int(c["number"]), make_cutter(float(c["diameter"]), kind=kind, key="tool"),
                float(c["spindle"]))


def _kinematics(k: dict) -> Kinematics:
    """The kinematics of a ``post.kinematics`` mapping, through the file model's
    ``KinematicsCfg`` (its checks ran when the file was loaded)."""
    from pydantic import ValidationError

    from evoplan.commands.machine_config import KinematicsCfg

    from ..spec.errors import one_line

    try:
        return KinematicsCfg.model_validate(k).build()
    except ValidationError as e:
        raise ValueError(one_line(e, "post.kinematics")) from None
    except ValueError as e:
        raise ValueError(f"post.kinematics: {e}") from None


def _clearance_plane(k: dict, z_top: float) -> float:
    """The clearance plane's Z: ``clearance_plane`` (absolute, not below the stock top) or
    ``clearance_height`` above the stock top. Checked here, not in the file model: the stock
    top is known only once the surface is built."""
    plane = k.get("clearance_plane")
    if plane is None:
        return z_top + float(k.get("clearance_height", 20.0))
    if plane < z_top:
        raise ValueError(f"post.kinematics.clearance_plane: {plane:g} is below the stock top z = {z_top:.3f}")
    return float(plane)


def _finish_problem(surface, params: dict):
    """The toolpath problem that plans the finish: the run's (or the file's) params on this
    surface. Only one plan is made, so the objective's normalization design is skipped (any
    weights and normalization: the path does not depend on them)."""
    from ..problem import ToolpathProblem

    params = {k: v for k, v in params.items() if k not in ("weights", "objectives",
                                                         "normalization", "simulation")}
    return ToolpathProblem(**params, surface=surface, weights={"cc_count": 1.0},
                           normalization={"cc_count": [0.0, 1.0]}, criteria="analytic")


def _finish_plan(surface, cfg: dict, plan):
    """(Toolpath, variables) of the finish: the decision set of ``finish.params`` with
    ``finish.problem``, or a finished run's best decision set with the run's whole problem
    (``plan``: (variables, params); a zoned or 3-axis run gives its own plan)."""
    fin = cfg["finish"]
    if plan is not None:
        variables, run_params = plan
        run_surface = parse_surface(run_params.get("surface", "fountas"), "surface",
                                    run_params.get("base_dir"))  # a run's files: its run file's folder
        uv = np.linspace(0, 1, 7)
        if not np.allclose(run_surface.points(uv, uv[::-1]), surface.points(uv, uv[::-1]), atol=1e-6):
            raise ValueError("surface: the --from-run run optimized another surface")
        params = {k: v for k, v in run_params.items() if k != "surface"}
        where = "--from-run"
    else:
        variables, params = fin["params"], dict(fin["problem"])  # its keys checked on load
        where = "finish"
    params.setdefault("feed_rate", fin["feed"])
    try:
        problem = _finish_problem(surface, params)
    except ValueError as e:
        raise ValueError(f"{where}.problem.{e}") from None
    try:
        return finish_from_plan(problem, variables, int(fin["tool"]["number"]), float(fin["tool"]["spindle"]),
                                plunge_feed=float(fin["plunge_feed"])), variables
    except ValueError as e:
        raise ValueError(f"{where}.{e}") from None


def _check_axes(post_cls, cfg: dict, plan) -> None:
    """A 3-axis post cannot take a 5-axis finish: refused before any operation is planned.
    Checked here, not in the file model: a ``--from-run`` plan brings its own machine."""
    fin = cfg["finish"]
    if post_cls.five_axis or fin["source"] != "plan":
        return
    params, where = (plan[1], "--from-run") if plan is not None else (fin["problem"], "finish.problem")
    if params.get("machine", "5axis") == "5axis":
        others = ", ".join(sorted(name for name, c in POSTS.items() if c.five_axis))
        raise ValueError(f"post.dialect: {post_cls.name} is a 3-axis post and the finish is 5-axis ({where}."
                         f"machine: 5axis): use a 5-axis post ({others}), {where}.machine: 3axis, or "
                         "finish.source: offset")


def _program_time(post, text: str, rapid_rate: float) -> float:
    """Kinematic time (min) of the program as written, read back by its post: S-curve feed
    moves (the default limits, the program's feeds), rapids at ``rapid_rate``, repositions
    included, a rotary turn in a rapid at the kinematics' ``rapid_rotary``."""
    mv = post.read(text)
    ok = np.isfinite(mv.tip).all(axis=1)  # the header's moves before X Y Z are all known
    kin = post.machine.kinematics
    return moves_time(mv.tip[ok], mv.rapid[ok], mv.feed[ok], Dynamics(rapid=rapid_rate),
                      mv.angles[ok] if kin is not None else None, kin.rapid_rotary if kin is not None else None)


def build_operations(cfg: dict, base_dir=None, plan=None, max_bytes: float | None = None,
                     progress=None) -> tuple[dict[str, bytes], dict]:
    """(files, summary) of the whole operation set (module docstring); sizes checked first
    against ``max_bytes`` and the ceilings of :mod:`.budget`."""
    surface = parse_surface(cfg["surface"], "surface", base_dir)
    check_sizes(cfg, surface, max_bytes)
    post_cfg = cfg["post"]  # its dialect is a registered post (checked on load)
    post_cls = POSTS[post_cfg["dialect"]]
    _check_axes(post_cls, cfg, plan)
    kin = _kinematics(post_cfg["kinematics"]) if post_cls.five_axis else None
    st, al, ro = cfg["stock"], cfg["allowances"], cfg["roughing"]
    stock = block_stock(surface, st["cell"], st["top"], st["top_offset"])
    safe_z = _clearance_plane(post_cfg["kinematics"], stock.z_top)
    post = post_cls(Machine(kin, post_cfg["work_offset"], post_cfg["program_number"], safe_z=safe_z,
                            tolerance=post_cfg.get("tolerance")))
    rough_tool = _tool(ro["tool"])
    step = progress or (lambda name: None)  # called as each stage starts (a progress bar)
    step("roughing")
    rough, stats, (floor, layers) = roughing(
        stock, ro["method"], rough_tool, d_cut=ro["max_depth"], stepover=ro["stepover"] * rough_tool.diameter,
        allowance_semi=al["semifinish"], allowance_finish=al["finish"], feed=ro["feed"],
        plunge_feed=ro["plunge_feed"], tolerance=ro["tolerance"], rapid=post_cfg["rapid_rate"])
    se = cfg["semifinish"]
    semi_tool = _tool(se["tool"], "ball")
    step("semi-finish")
    semi, semi_folded = ball_on_offset(surface, semi_tool, allowance=al["finish"], stepover=se["stepover"],
                                       step=se["step"], feed=se["feed"], plunge_feed=se["plunge_feed"],
                                       name="semifinish")
    step("finish")
    fin = cfg["finish"]
    finish_info = {"source": fin["source"]}
    if fin["source"] == "plan":
        finish, variables = _finish_plan(surface, cfg, plan)
        finish_info["params"] = dict(variables)
        finish_info["from_run"] = plan is not None
    else:
        fin_tool = _tool(fin["tool"], "ball")
        finish, finish_info["folded_offset_points"] = ball_on_offset(
            surface, fin_tool, allowance=0.0, stepover=fin["stepover"], step=fin["step"], feed=fin["feed"],
            plunge_feed=fin["plunge_feed"], name="finish")
    ops = {"roughing": rough, "semifinish": semi, "finish": finish}
    files, summary = {}, {"name": cfg["name"], "post": post.name,
                          "surface": {**dict(zip(("z_min", "z_max"), surface_z_range(surface))),
                                      **surface.facts()},
                          "stock": {"z_top": stock.z_top, "x": [float(stock.grid.xs[0]), float(stock.grid.xs[-1])],
                                    "y": [float(stock.grid.ys[0]), float(stock.grid.ys[-1])], "cell": stock.grid.cell}}
    for name, tp in ops.items():
        step(f"post {name}")
        try:
            nc = post.program(tp, name).encode()
        except ReachError as e:
            raise ValueError(f"post.kinematics: {name}: {e}") from None
        except PostError as e:
            raise ValueError(f"post.dialect: {e}") from None
        safety = None
        if post.five_axis:
            safety = {**check_program(post, nc.decode(), safe_z).__dict__, "clearance_plane": safe_z,
                      "axis_error_deg": post.axis_error}
        apt = apt_toolpath(tp, part=f"{cfg['name']} {name}").encode()
        files[f"{name}{post.extension}"], files[f"{name}.apt"] = nc, apt  # .nc, Heidenhain .h, Siemens .mpf
        summary[name] = {"tool": {"number": tp.tool.number, "label": tp.tool.label()}, "points": len(tp.tip),
                         "nc_file": f"{name}{post.extension}",
                         "lengths_mm": tp.lengths(), "time_min": tp.time_minutes(post_cfg["rapid_rate"]),
                         "kinematic_time_min": _program_time(post, nc.decode(), post_cfg["rapid_rate"]),
                         "nc_bytes": len(nc), "nc_lines": nc.count(b"\n"), "apt_bytes": len(apt),
                         "multi_axis": tp.multi_axis, "safety": safety}
    summary["roughing"].update(stats)
    summary["semifinish"]["folded_offset_points"] = semi_folded
    summary["finish"].update(finish_info)
    step("files")
    files["surface.dxf"] = surface_dxf(surface)
    files["surface.stl"] = surface_stl(surface)
    files["toolpaths.dxf"] = toolpaths_dxf(ops)
    files["layers.png"] = layers_png(stock, floor, layers, ro["method"],
                                     f"{cfg['name']}: {ro['method']} roughing, {stats['n_layers']} layers, "
                                     f"D_cut {ro['max_depth']:g} mm")
    files["summary.json"] = json.dumps(summary, indent=2).encode()
    return files, summary
