"""Survey planning (seed 001, GRAVITAS): the `countersign.plan/1` problem, an exact solver
and draft orders built from its plan."""

from .draft import orders_from_plan
from .from_orders import CannotBuildProblem, problem_from_orders
from .model import FORMAT, PlanArea, PlanProblem, PlanReadError, PlanVehicle, problem_from_data
from .solver import Plan, PlanTimeout, PlanTooLarge, plan_energy, solve

__all__ = [
    "FORMAT",
    "CannotBuildProblem",
    "Plan",
    "PlanArea",
    "PlanProblem",
    "PlanReadError",
    "PlanTimeout",
    "PlanTooLarge",
    "PlanVehicle",
    "orders_from_plan",
    "plan_energy",
    "problem_from_data",
    "problem_from_orders",
    "solve",
]
