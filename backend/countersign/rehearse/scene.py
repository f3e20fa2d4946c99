"""The rehearsal's viser scene and GUI.

The scene is drawn in scene units of 100 m with depth exaggerated five times, so a 10 km
mission and a 50 m dive are both visible from one camera. Everything the supervisor must see
in the recording is a scene node, not GUI: the vehicle, its trail, the contacts and one
coloured marker with a text label per outcome (succeed green, fail amber, violate red), since
`get_scene_serializer` records scene messages only.

Only the rehearsal thread calls `Scene.frame`; GUI callbacks arrive on viser's executor and
only forward to the rehearsal, which takes its own lock.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Callable
from typing import Any, Literal

import numpy as np
import viser

from . import viser_adapter
from .geo import Point
from .label_layout import LabelSpacer, offset
from .sim import FAULTS, QUESTION, Event, Simulation
from .world import World

# viser's client whitens whatever is more than about twenty units from the camera, so every
# mission is scaled to a scene SCENE_SPAN units wide, centred on the origin, with the seafloor
# SCENE_DEPTH units down (depth is exaggerated: a 10 km mission is far wider than deep).
SCENE_SPAN = 12.0
SCENE_DEPTH = 1.6
FLOOR_GRID = 48
TRAIL_CHUNK = 200  # points per trail node: a node is re-sent while it fills, then frozen
MAX_TRAIL_NODES = 200
MAX_OUTCOME_MARKERS = 500
OUTCOME_COLOURS = {"succeed": (40, 170, 60), "fail": (235, 160, 20), "violate": (220, 40, 40)}
# The app's names for the outcomes (frontend/src/editor/graph.ts OUTCOME_LABEL); the words in
# labels are DESIGN.md's outcome names.
OUTCOME_LABELS = {"succeed": "Succeed", "fail": "Fail", "violate": "Violate (constraint)"}
OUTCOME_WORDS = {"succeed": "succeed", "fail": "fail", "violate": "violate"}
OUTCOME_LETTERS = {"succeed": "s", "fail": "f", "violate": "c"}  # graph.ts OUTCOME_LETTER
MAX_LEGS_DRAWN = 500
CHART_COLOUR = (150, 90, 200)
AREA_COLOUR = (40, 160, 220)
LANE_COLOUR = (220, 90, 60)
RECOVERY_COLOUR = (60, 180, 90)
TRAIL_COLOUR = (250, 230, 60)
CURRENT_GOAL_COLOUR = (255, 255, 255)
FAULT_LABELS = {
    "gps_loss": "GPS loss",
    "nav_drift": "Navigation drift",
    "leak": "Leak",
    "low_energy": "Low energy",
    "contact_close": "Contact closing",
}


def disable_sharing(server: viser.ViserServer) -> None:
    """No share links: hide the button and refuse the requests a modified client could still
    send (viser would otherwise open a public tunnel to this server). The app's proxy drops
    these messages too."""
    server.gui.configure_theme(show_share_button=False)
    for message_cls in viser_adapter.share_message_types():
        viser_adapter.replace_handler(server, message_cls, _drop)

    def refuse(verbose: bool = True) -> str | None:
        return None

    server.request_share_url = refuse  # type: ignore[method-assign]


def _drop(client_id: Any, message: Any) -> None:
    return None


class Scene:
    def __init__(
        self,
        server: viser.ViserServer,
        sim: Simulation,
        *,
        title: str,
        on_choose: Callable[[str], None],
        on_inject: Callable[[str], object],
        on_speed: Callable[[float | None], None],
        on_skip: Callable[[], None],
        speed: float | None,
        manual: bool,
        controls: bool = False,
    ) -> None:
        self.server = server
        self.sim = sim
        self._events_seen = 0
        self._markers = 0
        self._marker_handles: list[Any] = []
        self._trail_nodes = 0
        self._trail_start = 0  # index in sim.trail where the open trail node starts
        self._trail_len_drawn = 0
        self._run_index = 0
        self._current_area: str | None = None
        self._area_lines: dict[str, Any] = {}
        # Labels kept apart (label_layout.py); a run's markers are forgotten with the run.
        self._labels = LabelSpacer()
        x0, y0, x1, y1 = sim.world.extent
        self._centre = ((x0 + x1) / 2, (y0 + y1) / 2)
        self._h = SCENE_SPAN / max(x1 - x0, y1 - y0, 1.0)
        self._v = SCENE_DEPTH / max(sim.world.floor_base_m, 1.0)
        disable_sharing(server)
        server.scene.set_up_direction("+z")
        # Shadows cost most of a frame in a software-rendered browser (CI, remote desktops)
        # and add nothing to a chart of the sea.
        server.scene.configure_default_lights(cast_shadow=False)
        self._static(sim.world)
        self._static_labels = self._labels.mark()
        self.vehicle = server.scene.add_box(
            "/vehicle", color=(250, 200, 30), dimensions=(0.4, 0.12, 0.12),
            position=self.to_scene(*sim.vehicle.xy, sim.vehicle.depth),
        )
        self.vehicle_label = server.scene.add_label(
            "/vehicle/label", "vehicle", position=(0.0, 0.0, 0.15)
        )
        self.contacts: dict[str, Any] = {}
        self._draw_contacts()
        # In the app the page holds the one set of controls and the status: viser's
        # panel stays empty and minimised so that the scene is unobstructed. The CLI's viewer
        # has no page around it and keeps its controls in the panel.
        self.controls = controls
        if controls:
            self._gui(title, on_choose, on_inject, on_speed, on_skip, speed, manual)
        else:
            server.gui.configure_theme(show_share_button=False, show_logo=False)
            server.gui.main_panel.minimize()
        server.initial_camera.position = (0.0, -SCENE_SPAN * 0.8, SCENE_SPAN * 0.55)
        server.initial_camera.look_at = (0.0, 0.0, -SCENE_DEPTH / 2)

    def to_scene(self, x: float, y: float, depth: float = 0.0) -> tuple[float, float, float]:
        """Metres (x east, y north, depth down) to scene units."""
        return ((x - self._centre[0]) * self._h, (y - self._centre[1]) * self._h,
                -depth * self._v)

    # ------------------------------------------------------------------------------ static

    def _static(self, world: World) -> None:
        scene = self.server.scene
        x0, y0, x1, y1 = world.extent
        n = FLOOR_GRID
        xs = np.linspace(x0, x1, n)
        ys = np.linspace(y0, y1, n)
        vertices = np.array(
            [self.to_scene(x, y, world.seafloor_depth(x, y)) for y in ys for x in xs],
            dtype=np.float32,
        )
        faces = []
        for j in range(n - 1):
            for i in range(n - 1):
                a = j * n + i
                faces.append((a, a + 1, a + n))
                faces.append((a + 1, a + n + 1, a + n))
        scene.add_mesh_simple("/world/seafloor", vertices, np.array(faces, dtype=np.uint32),
                              color=(150, 130, 95), flat_shading=False, side="double",
                              cast_shadow=False, receive_shadow=False)
        surface = np.array([self.to_scene(x0, y0), self.to_scene(x1, y0), self.to_scene(x1, y1),
                            self.to_scene(x0, y1)], dtype=np.float32)
        scene.add_mesh_simple("/world/surface", surface, np.array([(0, 1, 2), (0, 2, 3)],
                              dtype=np.uint32), color=(60, 120, 200), opacity=0.18,
                              side="double", cast_shadow=False, receive_shadow=False)
        for area in world.areas.values():
            self._draw_area(area.id, area.title, area.polygon, area.centre,
                            LANE_COLOUR if area.is_lane else
                            RECOVERY_COLOUR if area.centre == world.recovery else AREA_COLOUR)
        for chart in world.charts:
            self._draw_area(f"chart_{chart.id}", chart.title, chart.polygon, chart.centre,
                            LANE_COLOUR if chart.is_lane else CHART_COLOUR, root="/charts")
        self._draw_legs(world)
        if world.generated_lane:
            lane = world.lanes[-1]
            self._draw_area("LANE_generated", lane.title, lane.polygon, lane.centre, LANE_COLOUR)
        scene.add_icosphere("/world/recovery", radius=0.1, color=RECOVERY_COLOUR,
                            position=self.to_scene(*world.recovery))
        if not any(area.centre == world.recovery for area in world.areas.values()):
            anchor = self.to_scene(*world.recovery)
            at = self._labels.place((anchor[0], anchor[1], anchor[2] + 0.2), "recovery point")
            scene.add_label("/world/recovery/label", "recovery point",
                            position=offset(at, anchor))

    def _draw_legs(self, world: World) -> None:
        """Each outcome edge's leg (verify/legs.py), coloured and lettered by its outcome, a
        little below the surface: the route the vehicle will fly between goals. Legs that share
        their middle (the outcomes between the same two goals) get one label of their letters."""
        letters: dict[tuple[float, float, float], list[str]] = {}
        for k, leg in enumerate(world.legs[:MAX_LEGS_DRAWN]):
            (ax, ay), (bx, by) = leg.line.coords[0], leg.line.coords[-1]
            a, b = self.to_scene(ax, ay, 0.2), self.to_scene(bx, by, 0.2)
            colour = OUTCOME_COLOURS[leg.outcome]
            node = f"/legs/{k}"
            self.server.scene.add_line_segments(node, np.array([[a, b]], dtype=np.float32),
                                                colour, thickness=0.015)
            middle = (round((a[0] + b[0]) / 2, 3), round((a[1] + b[1]) / 2, 3),
                      round((a[2] + b[2]) / 2, 3))
            # The letter only: legs between the same areas overlap, and so would long labels.
            shared = letters.setdefault(middle, [])
            if OUTCOME_LETTERS[leg.outcome] not in shared:
                shared.append(OUTCOME_LETTERS[leg.outcome])
        for k, (middle, shared) in enumerate(letters.items()):
            self.server.scene.add_label(f"/leg_labels/{k}", " ".join(shared),
                                        position=self._labels.place(middle, " ".join(shared)))

    def _draw_area(self, area_id: str, title: str, polygon: tuple[Point, ...], centre: Point,
                   colour: tuple[int, int, int], root: str = "/areas") -> None:
        scene = self.server.scene
        node = f"{root}/{_node_name(area_id)}"
        if len(polygon) >= 2:
            ring = [*polygon, polygon[0]]
            segments = np.array(
                [[self.to_scene(*ring[i], 0.5), self.to_scene(*ring[i + 1], 0.5)]
                 for i in range(len(ring) - 1)], dtype=np.float32)
            self._area_lines[area_id] = scene.add_line_segments(
                f"{node}/outline", segments, colour, thickness=0.03)
        if len(polygon) >= 3:
            vertices = np.array([self.to_scene(*p, 0.3) for p in polygon], dtype=np.float32)
            faces = np.array([(0, i, i + 1) for i in range(1, len(polygon) - 1)],
                             dtype=np.uint32)
            scene.add_mesh_simple(f"{node}/fill", vertices, faces, color=colour, opacity=0.25,
                                  side="double", cast_shadow=False, receive_shadow=False)
        scene.add_label(f"{node}/label", title,
                        position=self._labels.place(self.to_scene(*centre, -0.25 / self._v), title))

    def _draw_contacts(self) -> None:
        for contact in self.sim.world.contacts:
            if contact.id in self.contacts or contact.start_s > self.sim.time_s:
                continue
            x, y = contact.position(self.sim.time_s)
            handle = self.server.scene.add_box(
                f"/contacts/{contact.id}",
                color=(200, 60, 200) if contact.closing else (230, 230, 230),
                dimensions=(0.35, 0.12, 0.1),
                position=self.to_scene(x, y, -0.05 / self._v),
                wxyz=_yaw(math.atan2(contact.velocity[1], contact.velocity[0])),
            )
            self.server.scene.add_label(f"/contacts/{contact.id}/label",
                                        f"contact {contact.id}", position=(0.0, 0.0, 0.15))
            self.contacts[contact.id] = handle

    # ------------------------------------------------------------------------------ GUI

    def _gui(self, title: str, on_choose: Callable[[str], None],
             on_inject: Callable[[str], object], on_speed: Callable[[float | None], None],
             on_skip: Callable[[], None], speed: float | None, manual: bool) -> None:
        gui = self.server.gui
        gui.set_panel_label(title[:80])
        self.status = gui.add_markdown("Starting...")
        # The goal's title is the orders author's text: a read-only text field shows it as
        # text. viser's markdown passes raw HTML, so only the app's words (and escaped ids)
        # go into markdown.
        self.goal_title: Any = gui.add_text("Goal", "", disabled=True)
        self.question = gui.add_markdown("", visible=manual)
        self.outcome_buttons: dict[str, Any] = {}
        colours: dict[str, Literal["green", "yellow", "red"]] = {
            "succeed": "green", "fail": "yellow", "violate": "red"}
        for outcome, label in OUTCOME_LABELS.items():
            button = gui.add_button(label, color=colours[outcome], disabled=True,
                                    visible=manual,
                                    hint=f"End the current goal: {OUTCOME_WORDS[outcome]}")
            button.on_click(_forward(on_choose, outcome))
            self.outcome_buttons[outcome] = button
        gui.add_button("Skip to the next decision").on_click(
            lambda _: _call(on_skip))
        self.speed_slider = gui.add_slider(
            "Speed (x real time, 0 = auto)", min=0.0, max=5_000.0, step=1.0,
            initial_value=0.0 if speed is None else float(min(speed, 5_000.0)))

        @self.speed_slider.on_update
        def _(_: Any) -> None:
            value = float(self.speed_slider.value)
            on_speed(value if value > 0 else None)

        with gui.add_folder("Inject a fault"):
            for fault in FAULTS:
                gui.add_button(FAULT_LABELS.get(fault, fault)).on_click(
                    _forward(on_inject, fault))

    # ------------------------------------------------------------------------------ frames

    def frame(self) -> None:
        """Push the simulation's current state (called by the rehearsal thread only)."""
        sim = self.sim
        if len(sim.runs) - 1 != self._run_index:
            self._new_run(len(sim.runs) - 1)
        v = sim.vehicle
        with self.server.atomic():
            self.vehicle.position = self.to_scene(v.x, v.y, v.depth)
            self.vehicle.wxyz = _yaw(v.heading)
            self._draw_contacts()
            for contact in sim.world.contacts:
                handle = self.contacts.get(contact.id)
                if handle is not None:
                    x, y = contact.position(sim.time_s)
                    handle.position = self.to_scene(x, y, -0.05 / self._v)
            self._draw_trail()
            for event in sim.events[self._events_seen:]:
                self._event(event)
            self._events_seen = len(sim.events)
            self._highlight_goal()
            if self.controls:
                self._gui_state()

    def _new_run(self, index: int) -> None:
        # A tour restarts from the launch point: clear the previous path's trail and markers
        # (the recording keeps them in its timeline).
        self._run_index = index
        for k in range(self._trail_nodes + 1):
            self.server.scene.remove_by_name(f"/trail/{k}")
        self._trail_nodes = 0
        self._trail_start = 0
        self._trail_len_drawn = 0
        for handle in self._marker_handles:
            handle.remove()
        self._marker_handles.clear()
        self._labels.rewind(self._static_labels)

    def _draw_trail(self) -> None:
        """The trail is split in nodes of TRAIL_CHUNK points: only the open node is re-sent
        as it grows, so drawing stays linear in the trail's length."""
        trail = self.sim.trail
        if len(trail) == self._trail_len_drawn or self._trail_nodes >= MAX_TRAIL_NODES:
            return
        end = min(len(trail), self._trail_start + TRAIL_CHUNK + 1)
        points = [self.to_scene(*p) for p in trail[self._trail_start:end]]
        if len(points) >= 2:
            segments = np.array([[points[i], points[i + 1]] for i in range(len(points) - 1)],
                                dtype=np.float32)
            self.server.scene.add_line_segments(f"/trail/{self._trail_nodes}", segments,
                                                TRAIL_COLOUR, thickness=0.04)
        self._trail_len_drawn = end
        if end - self._trail_start > TRAIL_CHUNK:
            # Freeze this node; the next starts where it ended so the line stays continuous.
            self._trail_start = end - 1
            self._trail_nodes += 1

    def _event(self, event: Event) -> None:
        if event.kind == "outcome" and self._markers < MAX_OUTCOME_MARKERS:
            outcome = str(event.data.get("outcome"))
            x, y, depth = event.data.get("position", [0.0, 0.0, 0.0])
            colour = OUTCOME_COLOURS.get(outcome, (200, 200, 200))
            node = f"/outcomes/{self._markers}"
            anchor = self.to_scene(x, y, depth)
            self._marker_handles.append(self.server.scene.add_icosphere(
                node, radius=0.1, color=colour, position=anchor))
            # A goal inside a refinement by its last id (G1.2#3): the goals of one refinement
            # share an area, and their full ids made the markers' labels pile up there.
            goal = event.goal.rsplit("/", 1)[-1] if event.goal else event.goal
            text = f"{goal}: {OUTCOME_WORDS.get(outcome, outcome)}"
            at = self._labels.place((anchor[0], anchor[1], anchor[2] + 0.2), text)
            self.server.scene.add_label(f"{node}/label", text, position=offset(at, anchor))
            self._markers += 1
        elif event.kind == "fault":
            v = self.sim.vehicle
            node = f"/outcomes/fault{self._markers}"
            self._marker_handles.append(self.server.scene.add_label(
                node, event.text,
                position=self._labels.place(self.to_scene(v.x, v.y, v.depth), event.text)))
            self._markers += 1
        elif event.kind == "terminal":
            v = self.sim.vehicle
            self._marker_handles.append(self.server.scene.add_label(
                f"/outcomes/terminal{self._run_index}", event.text,
                position=self._labels.place(self.to_scene(v.x, v.y, -0.6 / self._v),
                                            event.text)))

    def _highlight_goal(self) -> None:
        active = self.sim.active
        area = active.goal.area if active else None
        if area == self._current_area:
            return
        world = self.sim.world
        for area_id, colour in ((self._current_area, None), (area, CURRENT_GOAL_COLOUR)):
            if area_id is None or area_id not in world.areas:
                continue
            geom = world.areas[area_id]
            if colour is None:
                colour = LANE_COLOUR if geom.is_lane else \
                    RECOVERY_COLOUR if geom.centre == world.recovery else AREA_COLOUR
            ring = [*geom.polygon, geom.polygon[0]]
            segments = np.array(
                [[self.to_scene(*ring[i], 0.5), self.to_scene(*ring[i + 1], 0.5)]
                 for i in range(len(ring) - 1)], dtype=np.float32)
            self.server.scene.add_line_segments(f"/areas/{_node_name(area_id)}/outline",
                                                segments, colour, thickness=0.03)
        self._current_area = area

    def _gui_state(self) -> None:
        sim = self.sim
        active = sim.active
        goal = f"**{markdown_text(active.goal.id)}**" if active else "none"
        title = active.goal.label if active else ""
        if self.goal_title.value != title:
            self.goal_title.value = title
        outcomes = ", ".join(f"{markdown_text(g)} {OUTCOME_WORDS[o]}" for g, o in
                             zip(sim.run.goals, sim.run.outcomes, strict=False)) or "none yet"
        hours, rem = divmod(int(sim.time_s), 3600)
        self.status.content = (
            f"**State:** {sim.state.replace('_', ' ')}  \n"
            f"**Goal:** {goal}  \n"
            f"**Outcomes:** {outcomes}  \n"
            f"**Time:** {hours}h{rem // 60:02d}m  "
            f"**Energy left:** {sim.energy_remaining_wh:.0f} Wh  \n"
            f"**Faults:** {markdown_text(', '.join(sorted(sim.active_faults))) or 'none'}"
        )
        waiting = sim.state == "waiting_for_outcome"
        for button in self.outcome_buttons.values():
            if button.disabled == waiting:
                button.disabled = not waiting
        if waiting and active and active.suggestion:
            self.question.content = (
                f"{QUESTION}  \n"
                f"_The simulation saw: {OUTCOME_WORDS[active.suggestion[0]]} "
                f"({markdown_text(active.suggestion[1])})._")
        elif waiting:
            self.question.content = QUESTION
        else:
            self.question.content = ""


_PUNCTUATION = frozenset("!\"#$%&'()*+,-./:;=?@[\\]^_`{|}~")
_ANGLES = {"<": "\u2039", ">": "\u203a"}


def markdown_text(text: str) -> str:
    """`text` for viser's markdown as text, never markup: every ASCII punctuation mark is
    backslash-escaped (CommonMark), and angle brackets, which could open raw HTML in
    renderers that skip escapes, become the look-alike quotation marks."""
    return "".join(_ANGLES.get(c) or (f"\\{c}" if c in _PUNCTUATION else c)
                   for c in text.replace("\r", " ").replace("\n", " "))


def _forward(callback: Callable[[str], object], value: str) -> Callable[[Any], None]:
    def handler(_: Any) -> None:
        # A click in the wrong state (double click, finished rehearsal) is ignored.
        with contextlib.suppress(ValueError):
            callback(value)

    return handler


def _call(callback: Callable[[], None]) -> None:
    with contextlib.suppress(ValueError):
        callback()


def _yaw(heading: float) -> tuple[float, float, float, float]:
    return (math.cos(heading / 2), 0.0, 0.0, math.sin(heading / 2))


def _node_name(text: str) -> str:
    return "".join(c if c.isalnum() or c in "_-" else "_" for c in text) or "_"
