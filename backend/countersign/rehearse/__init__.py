"""Rehearsal: simulation, default rules and the viser scene (DESIGN.md, Rehearsal)."""
