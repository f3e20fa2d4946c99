"""Rehearsal: contingency rules (default logic, seed 004) and the simulation built on them."""
