"""``factor_generations.png``: each level of a factor drawn in its own colour and marker (the
inner loop over runs once overwrote the level's index, so every level got the last run's style)."""

from __future__ import annotations

import numpy as np
import pandas as pd

from evoplan.study import figures


def test_each_level_has_its_own_colour_and_marker(monkeypatch):
    levels = [f"{v:g}" for v in np.linspace(0.1, 0.9, 6)]
    runs = pd.DataFrame([{"key": f"{lv}-{r}", "problem": "kubota", "dimension": 2, "factor": "infection_rate",
                          "level": lv, "status": "ok", "algorithm": "vega"} for lv in levels for r in range(3)])
    history = lambda key: pd.DataFrame({"generation": range(5), "best": np.linspace(1, 0.1, 5) + 0.01})  # noqa: E731
    f_ref = pd.Series({("kubota", 2): 0.0})
    seen = {}
    monkeypatch.setattr(figures, "_png", lambda fig, caption="": seen.setdefault("fig", fig) and b"")
    figures.factor_generations(runs, history, f_ref)
    lines = [ln for ln in seen["fig"].axes[0].get_lines() if ln.get_label().startswith("infection_rate=")]
    assert [ln.get_label() for ln in lines] == [f"infection_rate={lv}" for lv in levels]
    styles = {(str(ln.get_color()), ln.get_marker()) for ln in lines}
    assert len(styles) == len(levels)
