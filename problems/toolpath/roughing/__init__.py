"""Roughing of a free-form surface from block stock: Abbas morphing layers, z-level baseline, stock Z-map, normal offsets."""
