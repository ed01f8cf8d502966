"""Finish-machining toolpath simulator for free-form surfaces."""
