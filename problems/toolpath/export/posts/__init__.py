"""Post-processors (one module per NC dialect) and their registry ``POSTS``."""

from . import fanuc, heidenhain, iso, siemens  # noqa: F401  (each registers itself)
from .base import POSTS, Machine, Moves, Post, PostError

__all__ = ["POSTS", "Machine", "Moves", "Post", "PostError"]
