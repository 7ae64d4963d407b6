"""Comparing two reports of the same surface (report.json, or rows of sweep.csv), timings aside.

TIMING_KEYS are the keys whose values depend on the machine, the clock or where a run was
interrupted and resumed, not on the surface computed; the test scripts that compare a resumed or
decomposed run with an uninterrupted one import them from here (PYTHONPATH=tests/support).
"""

TIMING_KEYS = frozenset({
    "wall_seconds", "solver_seconds", "measure_seconds", "geometry_seconds", "quality_seconds",
    "volume_seconds",
    "seconds_per_vcycle", "preview_seconds", "page_seconds", "write_seconds",
    "surface_mesh_seconds", "checkpoint_seconds", "peak_memory_bytes",
    "peak_memory_bytes_per_cell", "checkpoints_written", "resumed_from_step",
})


def differing_keys(a, b, ignore=()):
    """The keys of the dicts a and b, less TIMING_KEYS and ignore, whose values differ (a key
    present in one only differs), sorted."""
    skip = TIMING_KEYS | set(ignore)
    return sorted(k for k in set(a) | set(b) if k not in skip and a.get(k) != b.get(k))
