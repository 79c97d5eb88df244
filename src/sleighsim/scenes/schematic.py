"""The schematic kind: a figure drawn from its config block alone (no dataset, nothing integrated)."""

from __future__ import annotations

from sleighsim.scenes.kind import SceneKind

SCHEMATIC = SceneKind(
    name="schematic",
    title="schematic of the sleigh, its runner and the rotor (figure F1)",
    dataset=False, integrates=False, records=lambda c: [])
