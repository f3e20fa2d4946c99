"""Built-in maritime vocabulary: names, types, units and physical domains that orders may use
without declaring them. An entry in the orders' own `quantities` replaces the built-in one."""

from __future__ import annotations

from ..model import Orders, Quantity

MARITIME_QUANTITIES: dict[str, Quantity] = {
    name: Quantity.model_validate(spec)
    for name, spec in {
        "depth_m": {"unit": "m", "min": 0, "title": "depth"},
        "altitude_m": {"unit": "m", "min": 0, "title": "altitude above the seabed"},
        "speed_mps": {"unit": "m/s", "min": 0, "title": "speed"},
        "heading_deg": {"unit": "deg", "min": 0, "max": 360, "title": "heading"},
        "pitch_deg": {"unit": "deg", "min": -90, "max": 90, "title": "pitch"},
        "roll_deg": {"unit": "deg", "min": -180, "max": 180, "title": "roll"},
        "latitude_deg": {"unit": "deg", "min": -90, "max": 90, "title": "latitude"},
        "longitude_deg": {"unit": "deg", "min": -180, "max": 180, "title": "longitude"},
        "lane_distance_m": {"unit": "m", "min": 0,
                            "title": "distance to the nearest shipping lane"},
        "contact_distance_m": {"unit": "m", "min": 0,
                               "title": "distance to the nearest surface contact"},
        "contact_detection_range_m": {"unit": "m", "min": 0,
                                      "title": "surface contact detection range"},
        "contact_count": {"type": "integer", "min": 0, "title": "number of surface contacts"},
        "shore_distance_m": {"unit": "m", "min": 0, "title": "distance to shore"},
        "base_distance_m": {"unit": "m", "min": 0, "title": "distance to the recovery point"},
        "nav_error_m": {"unit": "m", "min": 0, "title": "navigation error"},
        "current_mps": {"unit": "m/s", "min": 0, "title": "water current"},
        "wave_height_m": {"unit": "m", "min": 0, "title": "wave height"},
        "sea_state": {"type": "integer", "min": 0, "max": 9, "title": "sea state"},
        "visibility_m": {"unit": "m", "min": 0, "title": "visibility"},
        "water_temperature_c": {"unit": "degC", "min": -5, "max": 45,
                                "title": "water temperature"},
        "battery_pct": {"unit": "%", "min": 0, "max": 100, "title": "battery charge"},
        "battery_reserve_pct": {"unit": "%", "min": 0, "max": 100, "title": "battery reserve"},
        "energy_wh": {"unit": "Wh", "min": 0, "title": "energy used"},
        "duration_s": {"unit": "s", "min": 0, "title": "elapsed time"},
        "elapsed_s": {"unit": "s", "min": 0, "title": "elapsed time"},
        "comms_ok": {"type": "boolean", "title": "communications link up"},
        "gps_fix": {"type": "boolean", "title": "GPS fix"},
        "surfaced": {"type": "boolean", "title": "surfaced"},
        "safety_equipment_ok": {"type": "boolean", "title": "safety equipment functional"},
        "mission_systems_ok": {"type": "boolean", "title": "mission systems operational"},
    }.items()
}


def quantity_table(orders: Orders) -> dict[str, Quantity]:
    """Every quantity an expression in these orders may read: the built-in vocabulary, then
    the orders' own declarations (which win), then names that only appear in an envelope or
    that a feature of the target vehicle measures (real numbers without a domain)."""
    table = dict(MARITIME_QUANTITIES)
    table.update(orders.quantities)
    implicit: list[str] = []
    for goal in orders.goals:
        implicit.extend(goal.envelope)
    vehicle = orders.target_vehicle()
    if vehicle is not None:
        implicit.extend(vehicle.envelope)
        for feature in vehicle.features:
            implicit.extend(feature.measures)
    for name in implicit:
        if name not in table:
            table[name] = Quantity()
    return table
