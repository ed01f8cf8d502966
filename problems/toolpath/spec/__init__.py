"""The typed toolpath specification: a run file's toolpath ``params`` as one pydantic model.

- ``model``: :class:`ToolpathSpec`, composed from the registries' settings models;
- ``tools``: one tool's settings (a registered cutter plus id and cutting data) and the
  database they build;
- ``zoning``: the zoning method and its settings;
- ``fields`` / ``errors``: the checked number types and the one-line error form.
"""

from .model import ToolpathSpec
from .tools import TOOL_TEXT, ToolList, ToolSettings, parse_tools, tool_database, tool_from_text
from .zoning import ZoningSettings

__all__ = ["ToolpathSpec", "ToolSettings", "ToolList", "ZoningSettings",
           "TOOL_TEXT", "parse_tools", "tool_database", "tool_from_text"]
