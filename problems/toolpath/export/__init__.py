"""NC output of a toolpath: APT CL files (write and read back)."""
