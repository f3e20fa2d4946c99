"""Countersign: verify, rehearse and sign ethical mission orders for uncrewed vehicles."""

__version__ = "0.1.0"
