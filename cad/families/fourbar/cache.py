"""What the four-bar's build cache key hashes beyond the design object (the family's
``cache_inputs`` hook): the user handle script's content. A module of its own so that an
up-to-date build (a cache hit) imports no layout code."""

from __future__ import annotations

from cad.parts.handle import resolve_script, script_sha256


def cache_inputs(design) -> dict:
    """Inputs outside the design object: the user handle script's content (sha256)."""
    p = resolve_script(design.parts, design.source)
    return {"handle_script_sha256": script_sha256(p) if p is not None else None}
