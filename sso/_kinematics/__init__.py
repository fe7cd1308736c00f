"""Physics of the mechanisms: Hooke-joint chains and planar linkages (no I/O)."""
