"""One viser scene for a team's rehearsal: every vehicle, its path, the meeting
points and what happened at them.

Each member's simulation flies in its own mission frame (its orders' areas); the scene
projects everything into one team frame (the verifier's azimuthal equidistant frame over all
members' areas), so areas the members share (Area C, the base) are drawn once and where they
are. Every vehicle has its own colour, and its vehicle id as a text label above it (a scene
label: text, never markup); its trail is drawn in that colour. Meeting points are white
spheres labelled with the meeting id; a meeting that happened, or a member left waiting, gets
a label at the place. Only the rehearsal thread calls `TeamScene.frame`.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import viser

from ..verify.legs import Frame, frame_for
from .geo import Point, bounds
from .label_layout import LabelSpacer, offset
from .scene import (
    AREA_COLOUR,
    LANE_COLOUR,
    OUTCOME_COLOURS,
    OUTCOME_WORDS,
    RECOVERY_COLOUR,
    SCENE_DEPTH,
    SCENE_SPAN,
    _node_name,
    _yaw,
    disable_sharing,
)
from .team import Member, TeamSimulation

# Distinct from the outcome colours (green, amber, red) and from each other.
VEHICLE_COLOURS: tuple[tuple[int, int, int], ...] = (
    (250, 200, 30), (40, 200, 230), (230, 90, 200), (255, 140, 60),
    (150, 110, 250), (120, 230, 120), (250, 250, 250), (60, 110, 250))
MEETING_COLOUR = (255, 255, 255)
TRAIL_CHUNK = 200
MAX_TRAIL_NODES = 100  # per vehicle
MAX_MARKERS = 500


class TeamScene:
    def __init__(self, server: viser.ViserServer, team: TeamSimulation, *, title: str) -> None:
        self.server = server
        self.team = team
        areas = [a for m in team.members for a in m.orders.areas]
        self.team_frame: Frame = frame_for(areas) or Frame(0.0, 0.0)
        self._labels = LabelSpacer()
        self._events_seen = 0
        self._markers = 0
        self._met: set[tuple[str, float]] = set()
        self._trails: dict[str, tuple[int, int, int]] = {}  # vehicle -> (nodes, start, drawn)
        self._trail_xy: dict[str, list[tuple[float, float, float]]] = {}
        self._converted: dict[str, int] = {}
        # The members' areas in the team frame, each id once (the first member's wins).
        self._areas: dict[str, tuple[str, tuple[Point, ...], Point, tuple[int, int, int]]] = {}
        for member in team.members:
            world = member.sim.world
            for area in world.areas.values():
                if area.id in self._areas:
                    continue
                colour = LANE_COLOUR if area.is_lane else \
                    RECOVERY_COLOUR if area.centre == world.recovery else AREA_COLOUR
                self._areas[area.id] = (area.title, tuple(self._xy(member, area.polygon)),
                                        self._xy(member, [area.centre])[0], colour)
        points = [p for _, polygon, _, _ in self._areas.values() for p in polygon] or [(0, 0)]
        x0, y0, x1, y1 = bounds(points)
        margin = max(2_000.0, 0.15 * max(x1 - x0, y1 - y0))
        x0, y0, x1, y1 = x0 - margin, y0 - margin, x1 + margin, y1 + margin
        self._centre = ((x0 + x1) / 2, (y0 + y1) / 2)
        self._h = SCENE_SPAN / max(x1 - x0, y1 - y0, 1.0)
        floor = max(m.sim.world.floor_base_m for m in team.members)
        self._v = SCENE_DEPTH / max(floor, 1.0)
        self._extent = (x0, y0, x1, y1)
        disable_sharing(server)
        server.gui.configure_theme(show_share_button=False, show_logo=False)
        server.gui.main_panel.minimize()
        server.scene.set_up_direction("+z")
        server.scene.configure_default_lights(cast_shadow=False)
        self._static()
        self._meeting_points()
        self._static_labels = self._labels.mark()
        self.vehicles: dict[str, Any] = {}
        for k, member in enumerate(team.members):
            self._vehicle(k, member)
        server.initial_camera.position = (0.0, -SCENE_SPAN * 0.8, SCENE_SPAN * 0.55)
        server.initial_camera.look_at = (0.0, 0.0, -SCENE_DEPTH / 2)
        self.title = title

    # ------------------------------------------------------------------------------ frames

    def _xy(self, member: Member, points: Any) -> list[Point]:
        """A member's frame points in the team frame."""
        pts = list(points)
        if not pts:
            return []
        world = member.sim.world
        lats, lons = world.frame.to_latlon([p[0] for p in pts], [p[1] for p in pts])
        xs, ys = self.team_frame.to_xy(lats, lons)
        return [(float(x), float(y)) for x, y in zip(xs, ys, strict=True)]

    def to_scene(self, x: float, y: float, depth: float = 0.0) -> tuple[float, float, float]:
        return ((x - self._centre[0]) * self._h, (y - self._centre[1]) * self._h,
                -depth * self._v)

    def colour(self, vehicle: str) -> tuple[int, int, int]:
        index = self.team.vehicles.index(vehicle)
        return VEHICLE_COLOURS[index % len(VEHICLE_COLOURS)]

    # ------------------------------------------------------------------------------ static

    def _static(self) -> None:
        scene = self.server.scene
        x0, y0, x1, y1 = self._extent
        surface = np.array([self.to_scene(x0, y0), self.to_scene(x1, y0), self.to_scene(x1, y1),
                            self.to_scene(x0, y1)], dtype=np.float32)
        faces = np.array([(0, 1, 2), (0, 2, 3)], dtype=np.uint32)
        scene.add_mesh_simple("/world/surface", surface, faces, color=(60, 120, 200),
                              opacity=0.18, side="double", cast_shadow=False,
                              receive_shadow=False)
        floor = np.array([self.to_scene(x, y, SCENE_DEPTH / self._v) for x, y in
                          ((x0, y0), (x1, y0), (x1, y1), (x0, y1))], dtype=np.float32)
        scene.add_mesh_simple("/world/seafloor", floor, faces, color=(150, 130, 95),
                              side="double", cast_shadow=False, receive_shadow=False)
        for area_id, (title, polygon, centre, colour) in self._areas.items():
            node = f"/areas/{_node_name(area_id)}"
            if len(polygon) >= 2:
                ring = [*polygon, polygon[0]]
                segments = np.array(
                    [[self.to_scene(*ring[i], 0.5), self.to_scene(*ring[i + 1], 0.5)]
                     for i in range(len(ring) - 1)], dtype=np.float32)
                scene.add_line_segments(f"{node}/outline", segments, colour, thickness=0.03)
            if len(polygon) >= 3:
                vertices = np.array([self.to_scene(*p, 0.3) for p in polygon], dtype=np.float32)
                tris = np.array([(0, i, i + 1) for i in range(1, len(polygon) - 1)],
                                dtype=np.uint32)
                scene.add_mesh_simple(f"{node}/fill", vertices, tris, color=colour, opacity=0.25,
                                      side="double", cast_shadow=False, receive_shadow=False)
            scene.add_label(f"{node}/label", title,
                            position=self._labels.place(self.to_scene(*centre, -0.25 / self._v),
                                                        title))

    def _meeting_points(self) -> None:
        """Each meeting's place: where each member's meeting goal holds."""
        self.meeting_anchor: dict[str, tuple[float, float, float]] = {}
        for member in self.team.members:
            world = member.sim.world
            for goal_id, meet in sorted(member.meets.items()):
                place = world.places.get(goal_id)
                goal = member.orders.goal_index()[goal_id]
                area = world.areas.get(goal.area or "")
                at = place.start if place is not None else area.centre if area else None
                if at is None:
                    continue
                x, y = self._xy(member, [at])[0]
                anchor = self.to_scene(x, y)
                node = f"/meetings/{_node_name(meet)}/{_node_name(member.vehicle)}"
                self.server.scene.add_icosphere(node, radius=0.12, color=MEETING_COLOUR,
                                                position=anchor)
                if meet not in self.meeting_anchor:
                    self.meeting_anchor[meet] = anchor
                    text = f"meeting {meet}"
                    # The label's parent (/meetings/R1) is no node, so it is drawn in the
                    # scene's frame: its position is where the spacer placed it, not an offset
                    # from the meeting point (which drew it at the chart's centre, over the
                    # titles there).
                    self.server.scene.add_label(
                        f"/meetings/{_node_name(meet)}/label", text,
                        position=self._labels.place((anchor[0], anchor[1], anchor[2] + 0.35),
                                                    text))

    def _vehicle(self, k: int, member: Member) -> None:
        v = member.sim.vehicle
        x, y = self._xy(member, [v.xy])[0]
        node = f"/vehicles/{_node_name(member.vehicle)}_{k}"
        self.vehicles[member.vehicle] = self.server.scene.add_box(
            node, color=self.colour(member.vehicle), dimensions=(0.4, 0.12, 0.12),
            position=self.to_scene(x, y, v.depth))
        # The vehicle id is the orders author's text: a scene label shows it as text.
        # Stacked by team order, so two vehicles at one place (the meeting, the base) keep
        # their labels apart.
        self.server.scene.add_label(f"{node}/label", member.vehicle,
                                    position=(0.0, 0.0, 0.2 + 0.2 * k))
        self._trails[member.vehicle] = (0, 0, 0)
        self._trail_xy[member.vehicle] = []
        self._converted[member.vehicle] = 0

    # ------------------------------------------------------------------------------ frame

    def frame(self) -> None:
        with self.server.atomic():
            for member in self.team.members:
                v = member.sim.vehicle
                x, y = self._xy(member, [v.xy])[0]
                handle = self.vehicles[member.vehicle]
                handle.position = self.to_scene(x, y, v.depth)
                handle.wxyz = _yaw(v.heading)
                self._draw_trail(member)
            events = self.team.events
            for event in events[self._events_seen:]:
                self._event(event.vehicle, event.event.kind, event.event.data,
                            event.event.goal)
            self._events_seen = len(events)

    def _draw_trail(self, member: Member) -> None:
        trail = member.sim.trail
        converted = self._trail_xy[member.vehicle]
        done = self._converted[member.vehicle]
        if len(trail) < done:  # a new run cleared it
            converted.clear()
            done = 0
        if len(trail) > done:
            new = trail[done:]
            xy = self._xy(member, [(p[0], p[1]) for p in new])
            converted.extend((x, y, p[2]) for (x, y), p in zip(xy, new, strict=True))
            self._converted[member.vehicle] = len(trail)
        nodes, start, drawn = self._trails[member.vehicle]
        if len(converted) == drawn or nodes >= MAX_TRAIL_NODES:
            return
        end = min(len(converted), start + TRAIL_CHUNK + 1)
        points = [self.to_scene(*p) for p in converted[start:end]]
        index = self.team.vehicles.index(member.vehicle)
        if len(points) >= 2:
            segments = np.array([[points[i], points[i + 1]] for i in range(len(points) - 1)],
                                dtype=np.float32)
            self.server.scene.add_line_segments(
                f"/trails/{_node_name(member.vehicle)}_{index}/{nodes}", segments,
                self.colour(member.vehicle), thickness=0.04)
        if end - start > TRAIL_CHUNK:
            self._trails[member.vehicle] = (nodes + 1, end - 1, end)
        else:
            self._trails[member.vehicle] = (nodes, start, end)

    def _event(self, vehicle: str, kind: str, data: dict[str, Any], goal: str | None) -> None:
        if self._markers >= MAX_MARKERS:
            return
        member = self.team.member(vehicle)
        v = member.sim.vehicle
        x, y = self._xy(member, [v.xy])[0]
        anchor = self.to_scene(x, y, v.depth)
        text: str | None = None
        colour: tuple[int, int, int] | None = None
        if kind == "outcome":
            outcome = str(data.get("outcome"))
            px, py, depth = data.get("position", [v.x, v.y, v.depth])
            x, y = self._xy(member, [(px, py)])[0]
            anchor = self.to_scene(x, y, depth)
            colour = OUTCOME_COLOURS.get(outcome, (200, 200, 200))
            # Two vehicles' outcome labels crowd the scene: a marker each, and the words are
            # the page's (its event list); meetings, deadlocks and ends keep their labels.
            self.server.scene.add_icosphere(f"/events/{self._markers}", radius=0.06,
                                            color=colour, position=anchor)
            self._markers += 1
            return
        elif kind == "meeting":
            met = (str(data.get("meet")), round(float(self.team.time_s), 1))
            colour = MEETING_COLOUR
            if met in self._met:
                self.server.scene.add_icosphere(f"/events/{self._markers}", radius=0.08,
                                                color=colour, position=anchor)
                self._markers += 1
                return
            self._met.add(met)
            together = ", ".join([vehicle, *(str(v) for v in data.get("with", []))])
            text = f"{together} met at {data.get('meet')}: " \
                f"{OUTCOME_WORDS.get(str(data.get('outcome')), str(data.get('outcome')))}"
        elif kind == "deadlock":
            text = f"{vehicle} left waiting at {data.get('meet')}"
            colour = OUTCOME_COLOURS["violate"]
        elif kind == "terminal":
            text = f"{vehicle}: {'complete' if data.get('kind') == 'complete' else 'abort'}"
        if text is None:
            return
        node = f"/events/{self._markers}"
        if colour is not None:
            self.server.scene.add_icosphere(node, radius=0.08, color=colour, position=anchor)
        at = self._labels.place((anchor[0], anchor[1], anchor[2] + 0.2), text)
        self.server.scene.add_label(f"{node}/label", text, position=offset(at, anchor)
                                    if colour is not None else at)
        self._markers += 1
