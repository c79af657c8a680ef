#!/usr/bin/python3
"""Scores the UV mission in the simulated greenhouse against the simulator's truth (the only node that reads it):
thorvald_sim's truth file (rail sets, rail length) and ground_truth/odom (base_link in the world), with the
mission's own outputs (uv_lights, nav_vel, mission/status, mission/report, safety/lock, bumper/lock).

- on rails: the drive wheels (base_link) beyond a set's pipe start, before its end, within `lateral_tol` of the
  set's centre line. `lights_off_rails_s`: simulated time with the lights on while not on rails.
- wheel past an edge: base_link more than `drop` below its height on the floor at the start (taken 1 s after the
  first truth message, once it has settled from its spawn), or rolled or pitched by more than `tilt` (a rear rail
  wheel leaving its pipe pitches base_link, which is on the drive axle).
- rail yaw: `rail_yaw_max_abs_rad`, the largest truth heading off a set's line with base_link 1.5 m or more along its
  rails (the rear wheels past the bent start pieces) and short of its end: how far the pipes let the robot turn.
- a set counts as treated (truth) when the lights were on while on its rails from within `start_margin` of its
  start to within `end_margin` of its end.
- safety events: engagements of safety/lock and bumper/lock after the mission started; surface_monitor's reason
  for each (an edge under a wheel, or a range finder silent for its timeout, e.g. on a machine too loaded to
  deliver the readings in time).
- rail speed: truth speed while the lights are on and the mission commands its treatment speed (from
  `settle` s after it first does).
- people (thorvald_sim's sim/actors, truth): a person is in the protected zone when within `zone_radius` of
  base_link with the lights on (the lamps' reach), or when their body overlaps the robot's swept path while it
  drives: the corridor of the footprint's width (`footprint`: front and rear of the frame from base_link, half its
  width; the greenhouse robot's 0.2, 0.85, 0.46 m) from the footprint to beyond its leading edge in the direction of
  the commanded motion by what the robot covers in `swept_horizon` (1 s) at the commanded speed plus
  `swept_clearance` (0.3 m), or, the robot on a set's rails with the lights on, driving in or holding there
  (mission/safety "holding: ..."), their body reaching between that set's rails ahead of it (within
  `row_half_width`, 0.3 m, of the set's centre line: the rails' corridor, which the mission guards 5 cm wider). (Until 2026-12-07 the swept path was a
  half-disc of `zone_radius` ahead of base_link, which also took a person in the plant row beside a robot driving in
  with its lamps off; until later that day the row took a person's centre, not their body, so a person stepping in from
  the plant row entered it a body's radius late, after the mission had seen their side in its corridor.)
  `uv_on_with_person_events`: times the lights were on with a person in that zone, but for the stop's reaction: a
  person who steps into the zone of a robot with its lamps lit is in it with the lamps on until the robot has reacted
  (unless it saw them coming), which the stop latency measures and its goal allows 200 ms; such a time counts when
  it lasts `reaction_allowance` (0.2 s) or longer, the lamps coming on with a person in the zone counts at once.
  `uv_on_with_person_any` counts every time, reactions included, `uv_on_with_person_max_ms` the longest;
  `person_stop_latency_p99_ms`: from a person entering the zone to the mission's twist being zero with the lights
  off (0 when they already were; `person_zone_entries_moving` counts the entries that came while the robot moved or
  within `reaction_allowance` after it stopped (it saw the person coming and stopped just before their body was in
  the zone), `person_zone_entries_already_stopped` the others, e.g. a person stepping into the row ahead of a robot
  that already holds for them).
- `person_holds`, `phantom_person_holds`: the mission's holds for a person (mission/safety "holding: a person ... at
  (x, y) m", base_link), counted when each begins; a phantom when no person (truth) was within `phantom_radius` of
  that point then.
- `collisions`: every body contact that began (sim/contacts START: people, trolleys, walls), but a wheel on a
  ground geom (floor, bump, rail, hose: driving).
- `coverage_pct` per set (the issue's coverage): share of the row's length that got at least the set dose, in 5 cm
  bins (RowDoseBins, the same model as uv_dose's RowDose): the lamps' power spread over their lit stretch
  (config/uv_lamps.yaml, the one lamp geometry of uv_dose, uv_mission and this scorer) for the time each bin spends
  under it with the lamps on (the lamps' state below: the simulated relay's, or `uv_lights`), from the truth pose of
  base_link on the set's rails. The row is the plants' stretch beside the set, the truth file's `plants` per set
  (thorvald_sim: from `plant_row_start`, 1 m, past the rails' start to `plant_row_end_gap`, 1 m, before the end of
  the shorter set beside the row; a set without plants has no coverage figure). `coverage_rails_pct`: the same over the rails' own
  length (the truth file's `length`, else `rail_length`). `coverage_interlock_pct`: the rails' stretch with the lamps
  counted on only while the truth speed is within the interlock's band (`treat_speed` +- `interlock_tolerance`),
  as uv_interlock would switch the relay on the real robot. `coverage_base_link_pct`: the former figure, the share of
  the rails from `start_margin` to `end_margin` before their end that base_link passed over with the lights on.
Ends when the mission has finished (mission/status not running after it ran) or after `timeout` s of simulated
time, and prints `RESULT {json}`. Run as a node (sim_uv_mission.launch scorer:=true) or imported by the rostest."""
import json
import math
import re
import sys
import threading
import time

import rospy
import yaml
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from std_msgs.msg import Bool, String

try:
    from thorvald_sim.msg import ActorArray, BodyContact
except ImportError:  # no simulator messages: no people, no contacts
    ActorArray = BodyContact = None

from greenhouse_rail_nav.msg import SurfaceState
from thorvald_state_machine.msg import MachineStatus


def rpy(q):
    roll = math.atan2(2 * (q.w * q.x + q.y * q.z), 1 - 2 * (q.x * q.x + q.y * q.y))
    pitch = math.asin(max(-1.0, min(1.0, 2 * (q.w * q.y - q.z * q.x))))
    yaw = math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))
    return roll, pitch, yaw


def load_lamps(path):
    """The lamps' geometry and the set dose (config/uv_lamps.yaml)."""
    with open(path) as f:
        y = yaml.safe_load(f)
    return {k: float(y[k]) for k in ("lamp_power", "lamp_length", "lamp_offset", "target_dose")}


def default_lamps_file():
    import os
    return os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "config", "uv_lamps.yaml")


class RowDoseBins:
    """The UV dose along one row [J/m] in `bin_m` bins from `row_from` to `row_to` (set coordinates along its rails,
    m): base_link moving from `s0` to `s1` in `dt` s with the lamps on spreads lamp_power * dt evenly over the lit
    stretch [s + offset - length / 2, s + offset + length / 2] (sub-steps of a fifth of a bin)."""

    def __init__(self, lamps, row_from, row_to, bin_m=0.05):
        self.lamps, self.row_from, self.bin_m = lamps, row_from, bin_m
        self.n = max(0, int(math.ceil((row_to - row_from) / bin_m - 1e-9)))
        self.row_len = max(0.0, row_to - row_from)
        self.dose = [0.0] * self.n

    def add(self, s0, s1, dt, on):
        if not on or dt <= 0.0 or self.n == 0:
            return
        half, per_m = 0.5 * self.lamps["lamp_length"], self.lamps["lamp_power"] / self.lamps["lamp_length"]
        k = max(1, int(math.ceil(abs(s1 - s0) / (0.2 * self.bin_m))))
        for j in range(k):
            c = s0 + (s1 - s0) * (j + 0.5) / k + self.lamps["lamp_offset"] - self.row_from
            lo, hi = c - half, c + half
            for i in range(max(0, int(math.floor(lo / self.bin_m))), min(self.n - 1, int(math.floor(hi / self.bin_m))) + 1):
                overlap = min(hi, (i + 1) * self.bin_m) - max(lo, i * self.bin_m)
                if overlap > 0.0:
                    self.dose[i] += per_m * (dt / k) * overlap / self.bin_m

    def coverage_pct(self):
        """Share of the row's length with at least the set dose [%]."""
        if self.n == 0:
            return 100.0
        target = self.lamps["target_dose"] - 1e-9
        covered = sum(min(self.bin_m, self.row_len - i * self.bin_m) for i in range(self.n) if self.dose[i] >= target)
        return round(100.0 * covered / self.row_len, 1)

    def uncovered(self):
        """Stretches below the set dose, [from, to] in set coordinates [m], merged."""
        out = []
        for i in range(self.n):
            if self.dose[i] >= self.lamps["target_dose"] - 1e-9:
                continue
            a = self.row_from + i * self.bin_m
            b = min(self.row_from + self.row_len, a + self.bin_m)
            if out and abs(out[-1][1] - a) < 1e-9:
                out[-1][1] = b
            else:
                out.append([a, b])
        return [[round(a, 2), round(b, 2)] for a, b in out]


# Truth files written before thorvald_sim gave each set's `plants`: the rows ran from 0.5 m past the rails' start
# over `rail_length`.
OLD_PLANTS_FROM_RAIL_START = 0.5


def plants_of(s, rail_length):
    """The plants beside a rail set along it from its start, [from, to] [m] (thorvald_sim's truth: `plants`), None
    when it has none."""
    p = s.get("plants")
    if p is None:
        return [OLD_PLANTS_FROM_RAIL_START, OLD_PLANTS_FROM_RAIL_START + rail_length]
    return [float(p[0]), float(p[1])] if len(p) == 2 and float(p[1]) > float(p[0]) else None


def parse_report(text):
    rows = []
    lines = [l for l in text.strip().splitlines() if l.strip()]
    if not lines:
        return rows
    header = lines[0].split(",")
    for line in lines[1:]:
        # the result column is quoted and may hold commas
        first, rest = line.split(",\"", 1) if ",\"" in line else (line, "")
        result, tail = rest.rsplit("\",", 1) if rest else ("", "")
        cells = first.split(",") + [result] + (tail.split(",") if tail else [])
        rows.append(dict(zip(header, cells)))
    return rows


class UvMissionScorer:
    def __init__(self, truth_file, treat_speed=0.5, lateral_tol=0.04, drop=0.01, tilt=0.02, start_margin=1.0,
                 end_margin=1.5, settle=0.5, zone_radius=1.5, scenario="none", lamps_file="",
                 interlock_tolerance=0.1, footprint=(0.2, 0.85, 0.46), swept_horizon=1.0, swept_clearance=0.3,
                 row_half_width=0.3, reaction_allowance=0.2):
        with open(truth_file) as f:
            self.truth = yaml.safe_load(f)
        self.sets = self.truth["rail_sets"]
        self.rail_length = float(self.truth["rail_length"])
        self.lamps = load_lamps(lamps_file or default_lamps_file())
        self.interlock_tolerance = interlock_tolerance
        # per set: the dose over the plants' row, over the rails, and over the rails as the interlock would light them
        self.row_dose, self.rails_dose, self.interlock_dose = {}, {}, {}
        self.plants = {s["index"]: plants_of(s, self.rail_length) for s in self.sets}
        for s in self.sets:
            if self.plants[s["index"]]:  # a set without plants beside it has no row to cover
                self.row_dose[s["index"]] = RowDoseBins(self.lamps, *self.plants[s["index"]])
            self.rails_dose[s["index"]] = RowDoseBins(self.lamps, 0.0, self.set_length(s))
            self.interlock_dose[s["index"]] = RowDoseBins(self.lamps, 0.0, self.set_length(s))
        self.zone_radius, self.scenario = zone_radius, scenario
        self.front, self.rear, self.half_width = (float(v) for v in footprint)
        self.swept_horizon, self.swept_clearance = swept_horizon, swept_clearance
        self.row_half_width = row_half_width
        self.people = []  # (x, y, radius) of every person at the latest sim/actors
        self.pose = None  # (t, x, y, yaw) of base_link, truth
        self.in_zone = False
        self.zone_since = None  # a person entered the zone at this time and the robot has not yet stopped
        self.latencies = []
        self.zone_lock = threading.Lock()
        self.zone_t = float("-inf")  # the latest time update_zone was given
        self.moving_at = float("-inf")  # the latest zone update with the robot moving or its lights on
        self.entries_moving = []  # per zone entry: whether the robot moved within reaction_allowance before it
        self.uv_person_events = 0
        self.uv_person_since = None  # the lights on with a person in the zone since then (None: not now)
        self.uv_person_any = 0  # every time the lights were on with a person in the zone, reactions included
        self.uv_person_counted, self.uv_person_allowed = False, 0.0
        self.reaction_allowance = reaction_allowance
        self.lights_before = False  # the lights at the previous zone update
        self.uv_person_ms = []  # how long each of those lasted
        self.collisions = []
        self.lit_bins = {}  # set index -> set of 5 cm bins passed with the lights on
        self.person_min_m = float("inf")  # closest any person's body came to base_link
        self.person_holds = 0
        self.phantom_holds = []  # (t, x, y) in the world of the holds for a person where nobody was
        self.holding_person = False
        self.holding = False  # the mission holds (mission/safety "holding: ..."), for anything
        self.phantom_radius = 1.0
        self.treat_speed, self.lateral_tol, self.drop, self.tilt = treat_speed, lateral_tol, drop, tilt
        self.start_margin, self.end_margin, self.settle = start_margin, end_margin, settle
        self.lights = False
        self.cmd_v = self.cmd_w = 0.0
        self.cruise_since = None
        self.last = None  # (t, x, y)
        self.z0 = None
        self.t_first = None
        self.lights_on_s = 0.0
        self.lights_off_rails_s = 0.0
        self.lights_off_rails_where = None
        self.wheel_past_edge = 0
        self.edge_where = None
        self.max_tilt = 0.0
        self.max_drop = 0.0
        self.rail_yaw_max = 0.0  # largest |truth yaw - the set's yaw| with the whole robot on a set's straight rails
        self.rail_yaw_where = None
        self.on_set_span = {}  # set index -> [min x, max x] of base_link with the lights on, on its rails
        self.speeds = []
        self.safety_events = 0
        self.lock_reasons = []  # surface_monitor's reason for each engagement of its lock
        self.surface_locked = False
        self.locks = {}
        self.status = None
        self.ran = False
        self.t_start = None
        self.t_end = None
        self.report = []
        self.report_received = False
        self.path = []

    def set_length(self, s):
        return float(s.get("length", self.rail_length))

    def in_set(self, s, x, y):
        dx, dy = x - float(s["x"]), y - float(s["y"])
        c, si = math.cos(float(s["yaw"])), math.sin(float(s["yaw"]))
        return c * dx + si * dy, -si * dx + c * dy

    def on_rails(self, x, y):
        for s in self.sets:
            along, across = self.in_set(s, x, y)
            if 0.0 <= along <= self.set_length(s) and abs(across) <= self.lateral_tol:
                return s["index"], along
        return None, None

    def in_swept_path(self, fx, fy, pr):
        """A body of radius pr at (fx, fy) in base_link overlaps the path the footprint sweeps while driving."""
        if abs(fy) - pr >= self.half_width:
            return False
        reach = abs(self.cmd_v) * self.swept_horizon + self.swept_clearance
        if self.cmd_v > 1e-3:
            return fx + pr > -self.rear and fx - pr < self.front + reach
        if self.cmd_v < -1e-3:
            return fx - pr < self.front and fx + pr > -(self.rear + reach)
        return False

    def person_in_zone(self):
        """A person in the protected zone (truth): near the lit lamps, in the swept path, or in the row ahead."""
        if self.pose is None:
            return False
        _, x, y, yaw = self.pose
        c, si = math.cos(yaw), math.sin(yaw)
        idx, along = self.on_rails(x, y)
        for px, py, pr in self.people:
            fx, fy = c * (px - x) + si * (py - y), -si * (px - x) + c * (py - y)
            if self.lights and math.hypot(fx, fy) < self.zone_radius:
                return True
            if self.in_swept_path(fx, fy, pr):
                return True
            if idx is not None and (self.lights or self.cmd_v > 1e-3 or self.holding):
                s = [q for q in self.sets if q["index"] == idx][0]
                p_along, p_across = self.in_set(s, px, py)
                if abs(p_across) - pr < self.row_half_width and along < p_along <= self.set_length(s):
                    return True
        return False

    def update_zone(self, t):
        with self.zone_lock:  # called from the truth's and the actors' callbacks, which rospy runs in two threads
            # Their stamps interleave out of order by a message period: time here never runs backwards.
            self.zone_t = max(t, self.zone_t)
            self._update_zone(self.zone_t)

    def _update_zone(self, t):
        if self.pose is not None:
            for px, py, pr in self.people:
                self.person_min_m = min(self.person_min_m, math.hypot(px - self.pose[1], py - self.pose[2]) - pr)
        zone = self.person_in_zone()
        stopped = not self.lights and abs(self.cmd_v) < 1e-6 and abs(self.cmd_w) < 1e-6
        if zone and not self.in_zone:
            # Moving within the reaction allowance before: a stop timed on a moving robot (0 when the mission saw the
            # person's side reach the zone and stopped a few milliseconds before the truth says their body is in it).
            self.entries_moving.append(t - self.moving_at <= self.reaction_allowance)
            if stopped:
                self.latencies.append(0.0)
            else:
                self.zone_since = t
        if self.zone_since is not None and (stopped or not zone):
            self.latencies.append(t - self.zone_since)  # stopped, or the person left the zone first
            rospy.loginfo("uv_mission_scorer: a person in the zone from %.2f s: %s after %.0f ms" %
                          (self.zone_since, "stopped" if stopped else "left it", 1000.0 * self.latencies[-1]))
            self.zone_since = None
        if not stopped:
            self.moving_at = t
        uv = zone and self.lights
        if uv and self.uv_person_since is None:
            self.uv_person_any += 1
            self.uv_person_since = t
            # A person stepping into the zone of a lit robot: the stop's allowance; the lights coming on with a person
            # in the zone: none.
            self.uv_person_counted = False
            self.uv_person_allowed = self.reaction_allowance if not self.in_zone and self.lights_before else 0.0
            rospy.logwarn("uv_mission_scorer: lights on with a person in the zone at %.2f s" % t)
        if uv and not self.uv_person_counted and t - self.uv_person_since >= self.uv_person_allowed:
            self.uv_person_events += 1
            self.uv_person_counted = True
        if not uv and self.uv_person_since is not None:
            self.uv_person_ms.append(1000.0 * (t - self.uv_person_since))
            rospy.logwarn("uv_mission_scorer: ... for %.0f ms" % self.uv_person_ms[-1])
            self.uv_person_since = None
        self.in_zone, self.lights_before = zone, self.lights

    def on_safety(self, m):
        """A hold for a person begins: was anybody there (truth)? One hold until the mission says it is clear, however
        often its text changes meanwhile (a body at the corridor's side seen as a person in one scan, an obstacle in
        the next)."""
        self.holding = m.data.startswith("holding")
        if not self.holding:
            self.holding_person = False
            return
        found = re.search(r"a person [^(]*\(([-0-9.]+), ([-0-9.]+)\) m", m.data)
        if not found or self.holding_person or self.pose is None:
            return
        self.holding_person = True
        self.person_holds += 1
        t, x, y, yaw = self.pose
        bx, by = float(found.group(1)), float(found.group(2))
        wx, wy = x + math.cos(yaw) * bx - math.sin(yaw) * by, y + math.sin(yaw) * bx + math.cos(yaw) * by
        if all(math.hypot(px - wx, py - wy) > self.phantom_radius for px, py, _ in self.people):
            self.phantom_holds.append((round(t, 2), round(wx, 2), round(wy, 2)))
            rospy.logwarn("uv_mission_scorer: held for a person at (%.2f, %.2f) where nobody is (%s)" %
                          (wx, wy, m.data))

    def on_actors(self, m):
        self.people = [(a.x, a.y, a.radius) for a in m.actors if a.kind == "person"]
        self.update_zone(m.header.stamp.to_sec())

    GROUND = ("headland_floor", "headland_bump", "row_ground", "floor", "rail", "rusty_rail", "hose")

    def on_contact(self, m):
        # A wheel on the ground is driving, not a collision (thorvald_sim leaves these out, but not for every wheel
        # body and floor geom name: caster wheels on the headland floor's segments were reported).
        other = m.other.split("/")[-1]
        if "wheel" in m.robot_body and other.startswith(self.GROUND):
            return
        if m.event == 0:  # START
            self.collisions.append("%s-%s at (%.2f, %.2f), %.1f s" % (m.robot_body, m.other, m.x, m.y,
                                                                       m.header.stamp.to_sec()))
            rospy.logwarn("uv_mission_scorer: contact %s" % self.collisions[-1])

    SETTLE_S = 1.0  # [s] of simulated time from the first truth message

    # callbacks
    def on_truth(self, m):
        t = m.header.stamp.to_sec()
        p = m.pose.pose.position
        roll, pitch, yaw = rpy(m.pose.pose.orientation)
        if self.z0 is None:
            self.t_first = t
        if len(self.path) == 0 or math.hypot(p.x - self.path[-1][0], p.y - self.path[-1][1]) > 0.05:
            self.path.append((p.x, p.y))
        if t - self.t_first < self.SETTLE_S:
            # The robot is spawned a little above the floor and settles onto its wheels (about 1 cm): its height
            # on the floor is taken once it has stood there this long, before the mission moves it.
            self.z0 = p.z
            past = False
        else:
            self.max_tilt = max(self.max_tilt, abs(roll), abs(pitch))
            self.max_drop = max(self.max_drop, self.z0 - p.z)
            past = p.z < self.z0 - self.drop or abs(roll) > self.tilt or abs(pitch) > self.tilt
        if past and self.edge_where is None:
            self.edge_where = (round(p.x, 3), round(p.y, 3), round(p.z - self.z0, 4), round(roll, 4),
                               round(pitch, 4))
        if past and not getattr(self, "_past", False):
            self.wheel_past_edge += 1
        self._past = past
        self.pose = (t, p.x, p.y, yaw)
        self.track_rail_yaw(p.x, p.y, yaw)
        self.update_zone(t)
        if self.last is not None:
            dt = t - self.last[0]
            self.add_dose(self.last, (t, p.x, p.y))
            if dt > 0.0 and self.lights:
                self.lights_on_s += dt
                idx, along = self.on_rails(p.x, p.y)
                if idx is not None:
                    bins = self.lit_bins.setdefault(idx, set())
                    _, along0 = self.on_rails(self.last[1], self.last[2])
                    lo, hi = sorted((along if along0 is None else along0, along))
                    bins.update(range(int(lo / 0.05), int(hi / 0.05) + 1))
                if idx is None:
                    self.lights_off_rails_s += dt
                    if self.lights_off_rails_where is None:
                        self.lights_off_rails_where = (round(p.x, 3), round(p.y, 3))
                else:
                    span = self.on_set_span.setdefault(idx, [along, along])
                    span[0], span[1] = min(span[0], along), max(span[1], along)
                if (self.cruise_since is not None and t - self.cruise_since >= self.settle):
                    self.speeds.append(math.hypot(p.x - self.last[1], p.y - self.last[2]) / dt)
        self.last = (t, p.x, p.y)

    RAIL_YAW_FROM_M = 1.5  # [m] of base_link along a set: the rear wheels past the pipes' bent start pieces

    def track_rail_yaw(self, x, y, yaw):
        """How far the pipes let the robot turn: with base_link far enough along a set's rails that its rear wheels
        are on the straight pipes too, and short of the end."""
        idx, along = self.on_rails(x, y)
        if idx is None:
            return
        st = [q for q in self.sets if q["index"] == idx][0]
        if not self.RAIL_YAW_FROM_M <= along <= self.set_length(st) - 0.2:
            return
        d = abs(math.atan2(math.sin(yaw - float(st["yaw"])), math.cos(yaw - float(st["yaw"]))))
        if d > self.rail_yaw_max:
            self.rail_yaw_max = d
            self.rail_yaw_where = (idx, round(along, 2))

    def add_dose(self, a, b):
        """The lamps' dose between two truth samples (t, x, y) of base_link, on the rails of the set it is on."""
        dt = b[0] - a[0]
        if dt <= 0.0 or not self.lights:
            return
        idx, s1 = self.on_rails(b[1], b[2])
        if idx is None:
            return
        st = [q for q in self.sets if q["index"] == idx][0]
        s0, _ = self.in_set(st, a[1], a[2])
        if idx in self.row_dose:
            self.row_dose[idx].add(s0, s1, dt, True)
        self.rails_dose[idx].add(s0, s1, dt, True)
        speed = math.hypot(b[1] - a[1], b[2] - a[2]) / dt
        self.interlock_dose[idx].add(s0, s1, dt, abs(speed - self.treat_speed) <= self.interlock_tolerance)

    def on_lights(self, m):
        self.lights = m.data

    def on_cmd(self, m):
        self.cmd_v, self.cmd_w = m.linear.x, m.angular.z
        cruise = self.lights and abs(m.linear.x - self.treat_speed) < 1e-6
        if cruise and self.cruise_since is None:
            self.cruise_since = rospy.Time.now().to_sec()
        elif not cruise:
            self.cruise_since = None

    def on_lock(self, name, m):
        if m.data and not self.locks.get(name, False) and self.ran:
            self.safety_events += 1
            rospy.logwarn("uv_mission_scorer: %s engaged at %.1f s" % (name, rospy.Time.now().to_sec()))
        self.locks[name] = m.data

    def on_surface(self, m):
        if m.locked and not self.surface_locked and self.ran:
            self.lock_reasons.append(m.reason)
        self.surface_locked = m.locked

    def on_status(self, m):
        self.status = m
        if m.running and not self.ran:
            self.ran = True
            self.t_start = rospy.Time.now().to_sec()
        if self.ran and not m.running and self.t_end is None:
            self.t_end = rospy.Time.now().to_sec()

    def on_report(self, m):
        self.report = parse_report(m.data)
        self.report_received = True

    def subscribe(self):
        rospy.Subscriber("ground_truth/odom", Odometry, self.on_truth, queue_size=50)
        # The lamps' state: the relay board's truth (~lamps_relay, e.g. sim/io/io0: SimHardware's std_msgs/UInt8, bit
        # ~lamps_output), or the mission's uv_lights command where no relay is simulated (~lamps_relay "").
        relay = rospy.get_param("~lamps_relay", "")
        if relay:
            from std_msgs.msg import UInt8
            bit = int(rospy.get_param("~lamps_output", 0))
            rospy.Subscriber(relay, UInt8, lambda m: self.on_lights(Bool(data=bool((m.data >> bit) & 1))))
        else:
            rospy.Subscriber("uv_lights", Bool, self.on_lights)
        rospy.Subscriber("nav_vel", Twist, self.on_cmd)
        rospy.Subscriber("safety/lock", Bool, lambda m: self.on_lock("safety/lock", m))
        rospy.Subscriber("bumper/lock", Bool, lambda m: self.on_lock("bumper/lock", m))
        rospy.Subscriber("surface_monitor/state", SurfaceState, self.on_surface)
        rospy.Subscriber("mission/status", MachineStatus, self.on_status)
        rospy.Subscriber("mission/report", String, self.on_report)
        rospy.Subscriber("mission/safety", String, self.on_safety)
        if ActorArray is not None:
            rospy.Subscriber(rospy.get_param("~actors_topic", "/sim/actors"), ActorArray, self.on_actors)
            rospy.Subscriber(rospy.get_param("~contacts_topic", "/sim/contacts"), BodyContact,
                             self.on_contact, queue_size=100)

    def finished(self):
        return self.t_end is not None and self.report_received

    def wait(self, timeout_sim_s, wall_timeout_s=None):
        wall_deadline = None if wall_timeout_s is None else time.monotonic() + wall_timeout_s
        while not rospy.is_shutdown():
            now = rospy.Time.now().to_sec()
            if self.finished():
                return True
            if self.t_first is not None and now - self.t_first > timeout_sim_s:
                return False
            if wall_deadline is not None and time.monotonic() > wall_deadline:
                return False
            time.sleep(0.2)
        return False

    def result(self):
        uv_person_ms = list(self.uv_person_ms)
        if self.uv_person_since is not None and self.pose is not None:  # still lit with a person in the zone
            uv_person_ms.append(1000.0 * max(0.0, self.pose[0] - self.uv_person_since))
        good_sets = [int(r["rail_set"]) for r in self.report]
        treated_report = [int(r["rail_set"]) for r in self.report if r.get("treated") == "1"]
        treated_truth = []
        length = {s["index"]: self.set_length(s) for s in self.sets}
        for idx, (lo, hi) in sorted(self.on_set_span.items()):
            if lo <= self.start_margin and hi >= length[idx] - self.end_margin:
                treated_truth.append(idx)
        coverage_base_link = {}
        for s in self.sets:
            want = range(int(math.ceil(self.start_margin / 0.05)), int((length[s["index"]] - self.end_margin) / 0.05))
            lit = self.lit_bins.get(s["index"], set())
            coverage_base_link[str(s["index"])] = round(100.0 * sum(1 for b in want if b in lit) / max(1, len(want)), 1)
        coverage = {str(k): d.coverage_pct() for k, d in sorted(self.row_dose.items())}
        coverage_rails = {str(k): d.coverage_pct() for k, d in sorted(self.rails_dose.items())}
        coverage_interlock = {str(k): d.coverage_pct() for k, d in sorted(self.interlock_dose.items())}
        lat = sorted(self.latencies)
        p99 = lat[min(len(lat) - 1, int(math.ceil(0.99 * len(lat))) - 1)] * 1000.0 if lat else 0.0
        n_sets = len(self.sets)
        aligns = [float(r["align_attempts"]) for r in self.report if r.get("treated") == "1"]
        mean = sum(self.speeds) / len(self.speeds) if self.speeds else float("nan")
        std = (math.sqrt(max(0.0, sum(v * v for v in self.speeds) / len(self.speeds) - mean * mean))
               if self.speeds else float("nan"))
        total_s = (self.t_end - self.t_start) if (self.t_end and self.t_start) else float("nan")
        # The analyzer numbers the sets in its own order (not the world's): a set counts as treated when the
        # mission's report says so and the truth saw the lights over a set's rails, counted, not matched by index.
        both = treated_truth[:min(len(treated_report), len(treated_truth))]
        return {
            "rail_sets": n_sets,
            "rail_length_m": self.rail_length,
            "rail_sets_in_report": len(good_sets),
            "rail_sets_treated": len(both),
            "rail_sets_treated_pct": round(100.0 * len(both) / n_sets, 1) if n_sets else 0.0,
            "treated_by_report": treated_report,
            "treated_by_truth": treated_truth,
            "lights_spans_m": {str(k): [round(v[0], 2), round(v[1], 2)] for k, v in self.on_set_span.items()},
            "mission_outcome": self.status.last_outcome if self.status else "",
            "mission_finished": self.finished(),
            "safety_events": self.safety_events,
            "safety_events_edge": sum(1 for r in self.lock_reasons if "edge" in r),
            "safety_events_silent_sensor": sum(1 for r in self.lock_reasons if "silent" in r and "edge" not in r),
            "safety_lock_reasons": self.lock_reasons,
            "wheel_past_edge": self.wheel_past_edge,
            "wheel_past_edge_first": self.edge_where,
            "max_tilt_rad": round(self.max_tilt, 4),
            "max_drop_m": round(self.max_drop, 4),
            "rail_yaw_max_abs_rad": round(self.rail_yaw_max, 4),
            "rail_yaw_max_where": self.rail_yaw_where,
            "lights_on_s": round(self.lights_on_s, 2),
            "lights_off_rails_s": round(self.lights_off_rails_s, 3),
            "lights_off_rails_first": self.lights_off_rails_where,
            "rail_speed_mean_mps": round(mean, 4),
            "rail_speed_std_mps": round(std, 4),
            "rail_speed_samples": len(self.speeds),
            "align_attempts_mean": round(sum(aligns) / len(aligns), 2) if aligns else float("nan"),
            "cycle_min_per_rail_set": round(total_s / 60.0 / len(both), 2) if both else float("nan"),
            "total_min": round(total_s / 60.0, 2),
            "scenario": self.scenario,
            "uv_on_with_person_events": self.uv_person_events,
            "uv_on_with_person_any": self.uv_person_any,
            "uv_on_with_person_max_ms": round(max(uv_person_ms), 1) if uv_person_ms else 0.0,
            "person_zone_entries": len(self.latencies),
            "person_zone_entries_already_stopped": sum(1 for m in self.entries_moving if not m),
            "person_zone_entries_moving": sum(1 for m in self.entries_moving if m),
            "person_stop_latency_p99_ms": round(p99, 1),
            "person_stop_latency_max_ms": round(lat[-1] * 1000.0, 1) if lat else 0.0,
            "person_holds": self.person_holds,
            "phantom_person_holds": len(self.phantom_holds),
            "phantom_person_holds_first": self.phantom_holds[:5],
            "collisions": len(self.collisions),
            "person_min_distance_m": round(self.person_min_m, 2) if self.people else None,
            "collisions_first": self.collisions[:5],
            "coverage_pct": coverage,
            "coverage_min_pct": min(coverage.values()) if coverage else 0.0,
            "coverage_uncovered_m": {str(k): d.uncovered() for k, d in sorted(self.row_dose.items())},
            "coverage_row_m": {str(k): [round(v, 3) for v in p] for k, p in sorted(self.plants.items()) if p},
            "coverage_rails_pct": coverage_rails,
            "coverage_rails_uncovered_m": {str(k): d.uncovered() for k, d in sorted(self.rails_dose.items())},
            "coverage_interlock_pct": coverage_interlock,
            "coverage_base_link_pct": coverage_base_link,
            "coverage_base_link_min_pct": min(coverage_base_link.values()) if coverage_base_link else 0.0,
            "lamps": self.lamps,
        }


def make_scorer(truth_file, wait_s=120.0, **kwargs):
    """The scorer once the simulator runs: thorvald_sim writes its truth file before it publishes ground truth, so a
    file left by an earlier run is not read."""
    rospy.wait_for_message("ground_truth/odom", Odometry, timeout=wait_s)
    return UvMissionScorer(truth_file, **kwargs)


def main():
    rospy.init_node("uv_mission_scorer")
    s = make_scorer(rospy.get_param("~truth_file"), treat_speed=rospy.get_param("~treat_speed", 0.5),
                    zone_radius=rospy.get_param("~zone_radius", 1.5), scenario=rospy.get_param("~scenario", "none"),
                    lamps_file=rospy.get_param("~lamps_file", ""),
                    footprint=rospy.get_param("~footprint", [0.2, 0.85, 0.46]),
                    swept_horizon=rospy.get_param("~swept_horizon", 1.0),
                    swept_clearance=rospy.get_param("~swept_clearance", 0.3),
                    row_half_width=rospy.get_param("~row_half_width", 0.3),
                    reaction_allowance=rospy.get_param("~reaction_allowance", 0.2))
    timeout = float(rospy.get_param("~timeout", 900.0))
    s.subscribe()
    s.wait(timeout)
    out = s.result()
    if rospy.get_param("~path_file", ""):
        with open(rospy.get_param("~path_file"), "w") as f:
            json.dump(s.path, f)
    for r in s.report:
        print("rail set %s: %s" % (r.get("rail_set"), ", ".join("%s=%s" % kv for kv in r.items())), flush=True)
    print("RESULT " + json.dumps(out), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
