"""Limits that more than one part of Countersign enforces, each named once.

A leaf module (it imports nothing of ours), so that every layer uses the same number by name:
the reader and the web app's body limit, the approval store and the package verifier's clock
allowance, the decision rule and the route's request model. tests/core/test_limits.py refuses
the literals of these limits anywhere else.
"""

from __future__ import annotations

from datetime import timedelta

MIB = 1024 * 1024

# Orders, plan problems and rules files are read whole: at most this many bytes.
MAX_INPUT_BYTES = 8 * MIB
# A request body: orders at MAX_INPUT_BYTES plus room for the JSON around them (413 beyond).
MAX_BODY_BYTES = MAX_INPUT_BYTES + 1 * MIB
# An approved package (a tar), as the server builds it and the command line downloads it.
MAX_PACKAGE_BYTES = 64 * MIB

# How far ahead of this machine's clock a signed time may lie (statements, cosignatures,
# package timestamps, execution logs): other clocks drift.
CLOCK_SKEW = timedelta(minutes=5)

# Characters in a decision's, rejection's or revocation's reason.
MAX_REASON = 2000
