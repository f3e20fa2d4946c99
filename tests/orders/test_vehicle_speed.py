"""Vehicle speeds are bounded to a physical range, so no rehearsal clock overflows."""

from __future__ import annotations

import pytest
from pydantic import ValidationError

from countersign.orders.model import MAX_SPEED_MPS, Vehicle


@pytest.mark.parametrize("speed", [1e308, MAX_SPEED_MPS * 1.001])
def test_unphysical_vehicle_speed_is_refused_by_name(speed: float) -> None:
    with pytest.raises(ValidationError, match="speed_mps"):
        Vehicle(id="auv", speed_mps=speed)


def test_fast_but_physical_speed_is_kept() -> None:
    assert Vehicle(id="jet", speed_mps=MAX_SPEED_MPS).speed_mps == MAX_SPEED_MPS
