"""Shared swarm_sim test helpers."""

from __future__ import annotations

import pytest


def _tapering_record(path, line_span=2, k=2, B=2, span=6) -> str:
    """A small tapering-arch limits record: a line up to ``line_span`` widths, then an arch of
    ``k`` layers whose feet grow in blocks of ``B`` rows, up to ``span`` widths (seconds per run,
    where the thesis record's arches start at 15 widths and ~200 robots)."""
    from structure_fem.limits import StructureLevel, StructureLimits, tapered_arch_robots

    levels = (
        StructureLevel("line", "line", 1, 1, 1, line_span, 2.0, 0, tuple(3 * w for w in range(1, line_span + 1))),
        StructureLevel("arch-t", "arch", 2 * k, k, line_span + 1, span, 1.0, 1,
                       tuple(tapered_arch_robots(k, B, w)["total"] for w in range(line_span + 1, span + 1)),
                       taper_block_rows=B),
    )
    return str(StructureLimits(source="test", robot="cubot", clearance_mm=15.0, levels=levels).save(path))


@pytest.fixture(scope="session")
def tapering_record():
    """``tapering_record(path, line_span=2, k=2, B=2, span=6) -> path`` of a written record."""
    return _tapering_record
