"""The params of Choi's zoned 3-axis configuration (runs/choi_zoning_vega.yaml), for tests."""

from evoplan.problems.toolpath.tools import CHOI_TOOLS


def choi_zoning(mesh=(70, 70), method="kmeans", gene_range=None, **changes) -> dict:
    """``toolpath`` params: Choi's surface and four tools, 3-axis drop-cutter, passes spaced
    for h_c 0.254 mm, each zone fed along its optimized direction, ``method``'s zones over a
    ``mesh``, the tool and the method's gene free (``gene_range``), objective Djebali's Eq. 4
    total in mm."""
    gene = {"kmeans": "zones", "amas": "k_lz"}.get(method)
    params = {
        "surface": "choi", "tools": CHOI_TOOLS, "machine": "3axis", "placement": "drop",
        "spacing": "scallop", "h_c": 0.254, "delta_l": 40.0, "feed_angle": "optimized",
        "zoning": {"method": method, "mesh": list(mesh), "merge": False},
        "fixed": {"step": 1.0}, "weights": {"eq4_total": 1.0},
        "normalization": {"eq4_total": [0.0, 1.0]}}
    if gene is not None and gene_range is not None:
        params["ranges"] = {gene: list(gene_range)}
    return {**params, **changes}
