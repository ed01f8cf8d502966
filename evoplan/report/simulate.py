"""A simulate folder's report: ``simulation.json``'s measures with units, a bar chart of the
scallop distribution, per-zone figures, and the folder's deviation PNGs embedded."""

from __future__ import annotations

import base64
from pathlib import Path

from .folder import read_json
from .page import Section, note, table
from .units import is_number

#: unit by the key's suffix (simulation.json spells its units in the key: scallop_max_mm)
SUFFIX_UNITS = {"_mm": "mm", "_mm2": "mm²", "_seconds": "s", "seconds": "s", "_fraction": "fraction"}
#: the cutter's numbers (``Cutter.to_dict``): lengths in mm, a tapered ball's taper_angle in degrees
CUTTER_UNITS = {"diameter": "mm", "corner_radius": "mm", "taper_angle": "deg"}
PNGS = ("deviation_map.png", "deviation_hist.png")


def unit(key: str) -> str:
    return next((u for s, u in sorted(SUFFIX_UNITS.items(), key=lambda kv: -len(kv[0]))
                 if key.endswith(s)), "")


def field_unit(prefix: str, key: str, value) -> str:
    """The unit of one ``simulation.json`` field: none unless its value is a number (a cutter's
    ``type`` is a name); else by the key's suffix, a cutter's by :data:`CUTTER_UNITS` (an
    unknown cutter number: degrees if its name says angle, else mm)."""
    if not is_number(value):
        return ""
    if prefix == "cutter.":
        return CUTTER_UNITS.get(key, "deg" if "angle" in key else "mm")
    return unit(key)


def flat(data: dict, prefix: str = "") -> list[list]:
    """Scalar entries of ``data`` (nested dicts as ``a.b``) as rows key, value, unit."""
    rows = []
    for key, value in data.items():
        name = f"{prefix}{key}"
        if isinstance(value, dict):
            rows += flat(value, name + ".")
        elif isinstance(value, (int, float, str, bool)) or value is None:
            rows.append([name, "" if value is None else value, field_unit(prefix, key, value)])
    return rows


def sections(folder: Path) -> list[Section]:
    import plotly.graph_objects as go

    path = folder / "simulation.json"
    sim = read_json(path)
    out = [Section("Measures (simulation.json)", [table(["measure", "value", "unit"], flat(sim))])]
    scallop = {k.removeprefix("scallop_").removesuffix("_mm"): v for k, v in sim.items()
               if k.startswith("scallop_") and k.endswith("_mm") and isinstance(v, (int, float))}
    if scallop:
        order = [k for k in ("p50", "p90", "p99", "max", "mean") if k in scallop] + \
                [k for k in scallop if k not in ("p50", "p90", "p99", "max", "mean")]
        fig = go.Figure(go.Bar(x=order, y=[scallop[k] for k in order],
                               hovertemplate="scallop %{x}: %{y:.4f} mm<extra></extra>"))
        fig.update_layout(yaxis_title="scallop height (mm)", xaxis_title="statistic over the cells",
                          height=380, margin=dict(l=60, r=20, t=30, b=50))
        out.append(Section("Scallop distribution", [fig]))
    zones = sim.get("zones")
    if isinstance(zones, list) and zones and all(isinstance(z, dict) for z in zones):
        keys = list(dict.fromkeys(k for z in zones for k, v in z.items() if not isinstance(v, (dict, list))))
        rows = [[z.get(k, "") for k in keys] for z in zones]
        out.append(Section("Per zone", [table([f"{k} ({unit(k)})" if unit(k) else k for k in keys], rows)]))
    images = [name for name in PNGS if (folder / name).is_file()]
    if images:
        items = [note("The simulate command's figures, embedded (data URIs: nothing is fetched).")]
        for name in images:
            data = base64.b64encode((folder / name).read_bytes()).decode("ascii")
            items.append(f'<p><img alt="{name}" style="max-width:100%" '
                         f'src="data:image/png;base64,{data}"></p>')
        out.append(Section("Deviation figures", items))
    if (folder / "deviation.npz").is_file():
        from .deviation import deviation_figures, read_npz

        f3, f2, cap = deviation_figures(read_npz(folder / "deviation.npz"))
        out.insert(1, Section("Deviation map (deviation.npz)", [f3, note(cap), f2]))
    return out
