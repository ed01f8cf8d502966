"""Units of the toolpath problem's decisions (its genes, ``problems/toolpath/genes.py``'s table),
shared by the figures (:func:`evoplan.figure_style.gene_text`) and ``evoplan report``."""

GENE_UNITS = {
    "tool": "tool id", "stepover": "% of D", "lead": "deg", "tilt": "deg", "step": "mm",
    "zones": "zones", "k_lz": "", "feed_angle": "deg", "h_c": "mm",
}
