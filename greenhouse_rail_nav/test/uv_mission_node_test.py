#!/usr/bin/python3
"""uv_mission, the node, against a scripted greenhouse that this process plays over ROS: a kinematic robot that
follows nav_vel with a short lag (odometry/filtered, tf map -> odom -> base_link), a move_base action server that
puts the robot at the goal with a small error, the rail detector, the surface monitor, the lidar's far wall and the
bumper's lock. Two missions run in turn, each in its own namespace with its own rail sets file (test/data):

- treat: both good rail sets are treated, the uncertain one is skipped, lights on only on the rails;
- faults: ~stop preempts the mission on the rails of set 0 and ~start resumes there; move_base aborts every goal of
  set 1, which is skipped while set 2 is still treated; the bumper's lock pauses the treatment of set 2.
"""
import csv
import io
import math
import sys
import threading
import time
import unittest

import actionlib
import rospy
import rostest
import tf2_ros
import yaml
from geometry_msgs.msg import PoseWithCovarianceStamped, TransformStamped, Twist
from move_base_msgs.msg import MoveBaseAction
from nav_msgs.msg import Odometry
from sensor_msgs.msg import LaserScan
from std_msgs.msg import Bool, String
from std_srvs.srv import Trigger
from thorvald_state_machine.msg import MachineStatus

from thorvald_testing import Recorder, wait_for

from greenhouse_rail_nav.msg import RailDetectionStatus, SurfaceState

RATE_HZ = 50.0
LAG_S = 0.1  # the base's first-order response to nav_vel [s]
_STATIC = []  # every world's static transforms, sent together by one broadcaster (tf_static is latched)


def publish_static(transform):
    if not _STATIC:
        _STATIC.append(tf2_ros.StaticTransformBroadcaster())
    _STATIC.append(transform)
    _STATIC[0].sendTransform(_STATIC[1:])


RAIL_LENGTH = 2.0  # [m] along each rail set from its start on the headland edge
WALL_GAP = 1.0  # the far wall stands this far beyond the rails' end [m]
LIDAR_X = 0.45  # the lidar ahead of base_link [m]
GAUGE = 0.55  # between the two pipes of a set [m]
WHEEL_SENSORS = ((0.0, 0.30), (0.0, -0.30))  # down-facing range finders at the drive wheels (base_link) [m]
FRONT_SENSORS = ((0.52, 0.30), (0.52, -0.30))  # and ahead of them [m]
NAV_ERROR = (0.01, -0.008, 0.008)  # where move_base leaves the robot, in the goal's frame [m, m, rad]
MAP_TO_ODOM = (0.3, -0.2, 0.05)  # the localisation's offset between map and odometry [m, m, rad]
RANGES = {SurfaceState.FLOOR: 0.35, SurfaceState.RAIL: 0.295, SurfaceState.EDGE: 0.5}


def compose(a, b):
    c, s = math.cos(a[2]), math.sin(a[2])
    return (a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1], math.remainder(a[2] + b[2], math.tau))


def inverse(a):
    c, s = math.cos(a[2]), math.sin(a[2])
    return (-c * a[0] - s * a[1], s * a[0] - c * a[1], -a[2])


def common(surfaces):
    """The surface monitor's verdict for a group of sensors: an edge under any of them, else what they agree on."""
    if SurfaceState.EDGE in surfaces:
        return SurfaceState.EDGE
    return surfaces[0] if len(set(surfaces)) == 1 else SurfaceState.UNKNOWN


def pose_of(msg_pose):
    q = msg_pose.orientation
    return (msg_pose.position.x, msg_pose.position.y, 2.0 * math.atan2(q.z, q.w))


class World:
    """One scripted greenhouse and robot, talking to the uv_mission node in namespace `ns`."""

    def __init__(self, ns, rail_sets_file):
        with open(rail_sets_file) as f:
            sets = yaml.safe_load(f)["rail_sets"]
        self.targets = {s["index"]: tuple(s["target_pose"][k] for k in ("x", "y", "yaw")) for s in sets}
        self.rails = [tuple(s["rail_frame"][k] for k in ("x", "y", "yaw")) for s in sets]
        self.ns, self.map_frame = ns, ns + "/map"
        self.lock = threading.Lock()
        self.pose = (-2.0, 0.8, 0.0)  # map frame, somewhere on the headland
        self.v = self.w = 0.0
        self.cmd = (0.0, 0.0)
        self.wheels = self.front = SurfaceState.FLOOR
        self.still_since = time.monotonic()
        self.lights = False
        self.abort_sets = set()
        # What the tests check.
        self.twists = []  # every nav_vel command, (linear, angular)
        self.lights_msgs = []  # every uv_lights message with the pose and the surface under the wheels then
        self.lights_off_rails = []  # poses where the lights were on with the wheels not on rails
        self.goals = []  # (rail set or None, pose, frame) of every move_base goal
        self.goal_wheels = []  # the wheel sensors' surface when each goal came
        self.initial_poses = []
        self.running = False
        self.odom_pub = rospy.Publisher(ns + "/odometry/filtered", Odometry, queue_size=5)
        self.rail_pub = rospy.Publisher(ns + "/rail_detection", RailDetectionStatus, queue_size=5)
        self.surface_pub = rospy.Publisher(ns + "/surface_monitor/state", SurfaceState, queue_size=5)
        self.scan_pub = rospy.Publisher(ns + "/scan", LaserScan, queue_size=2)
        self.bumper_pub = rospy.Publisher(ns + "/bumper/lock", Bool, queue_size=5, latch=True)
        self.tf = tf2_ros.TransformBroadcaster()
        # The lidar's mount: the mission evaluates its people and obstacle zone in base_link.
        mount = TransformStamped()
        mount.header.stamp = rospy.Time.now()
        mount.header.frame_id, mount.child_frame_id = ns + "/base_link", ns + "/laser"
        mount.transform.translation.x, mount.transform.rotation.w = LIDAR_X, 1.0
        publish_static(mount)
        rospy.Subscriber(ns + "/nav_vel", Twist, self.on_twist, queue_size=50)
        rospy.Subscriber(ns + "/uv_lights", Bool, self.on_lights, queue_size=50)
        rospy.Subscriber(ns + "/initialpose", PoseWithCovarianceStamped, self.initial_poses.append, queue_size=5)
        self.status = Recorder(ns + "/mission/status", MachineStatus)
        self.report = Recorder(ns + "/mission/report", String)
        self.move_base = actionlib.SimpleActionServer(ns + "/move_base", MoveBaseAction, self.navigate, False)
        self.move_base.start()
        self.start_srv = rospy.ServiceProxy(ns + "/uv_mission/start", Trigger)
        self.stop_srv = rospy.ServiceProxy(ns + "/uv_mission/stop", Trigger)

    # The robot.
    def on_twist(self, m):
        with self.lock:
            self.cmd = (m.linear.x, m.angular.z)
            self.twists.append(self.cmd)

    def on_lights(self, m):
        with self.lock:
            self.lights = m.data
            self.lights_msgs.append((m.data, self.pose, self.wheels))

    def navigate(self, goal):
        target = pose_of(goal.target_pose.pose)
        index = next((i for i, t in self.targets.items() if math.dist(t[:2], target[:2]) < 1e-3), None)
        self.goals.append((index, target, goal.target_pose.header.frame_id))
        self.goal_wheels.append(self.wheels)
        if index in self.abort_sets:
            self.move_base.set_aborted(text="scripted abort of rail set %d" % index)
            return
        end = time.monotonic() + 0.3
        while time.monotonic() < end:
            if self.move_base.is_preempt_requested():
                self.move_base.set_preempted()
                return
            time.sleep(0.02)
        with self.lock:
            self.pose = compose(target, NAV_ERROR)
            self.v = self.w = 0.0
            self.cmd = (0.0, 0.0)
        self.move_base.set_succeeded()

    def nearest_rails(self, pose):
        """The rail set laterally nearest to `pose`, and the pose in its rail frame."""
        in_rails = [compose(inverse(r), pose) for r in self.rails]
        return min(enumerate(in_rails), key=lambda p: abs(p[1][1]))

    def surface_at(self, lx, ly):
        _, (x, y, _) = self.nearest_rails(compose(self.pose, (lx, ly, 0.0)))
        if x < 0.0:
            return SurfaceState.FLOOR
        return SurfaceState.RAIL if x < RAIL_LENGTH and abs(abs(y) - 0.5 * GAUGE) < 0.05 else SurfaceState.EDGE

    def step(self, dt):
        with self.lock:
            a = min(1.0, dt / LAG_S)
            self.v += a * (self.cmd[0] - self.v)
            self.w += a * (self.cmd[1] - self.w)
            x, y, yaw = self.pose
            yaw += self.w * dt
            self.pose = (x + self.v * math.cos(yaw) * dt, y + self.v * math.sin(yaw) * dt, yaw)
            index, in_rail = self.nearest_rails(self.pose)
            if self.wheels == SurfaceState.RAIL and in_rail[0] > 0.1 and abs(in_rail[1]) < 0.05:
                self.pose = compose(self.rails[index], (in_rail[0], 0.0, 0.0))  # the pipes guide the rail wheels
            self.wheels = common([self.surface_at(*p) for p in WHEEL_SENSORS])
            self.front = common([self.surface_at(*p) for p in FRONT_SENSORS])
            if self.lights and self.wheels != SurfaceState.RAIL:
                self.lights_off_rails.append(self.pose)
            if abs(self.v) > 1e-3 or abs(self.w) > 1e-3:
                self.still_since = time.monotonic()

    def still_for(self):
        return time.monotonic() - self.still_since

    def in_rails(self):
        """The rail set nearest to the robot and base_link's pose in its rail frame."""
        with self.lock:
            return self.nearest_rails(self.pose)

    # The sensors.
    def publish(self, now, detect, scan):
        with self.lock:
            pose, v, w, wheels, front = self.pose, self.v, self.w, self.wheels, self.front
        odom = compose(inverse(MAP_TO_ODOM), pose)
        transforms = []
        for parent, child, p in (("map", "odom", MAP_TO_ODOM), ("odom", "base_link", odom)):
            t = TransformStamped()
            t.header.stamp, t.header.frame_id, t.child_frame_id = now, self.ns + "/" + parent, self.ns + "/" + child
            t.transform.translation.x, t.transform.translation.y = p[0], p[1]
            t.transform.rotation.z, t.transform.rotation.w = math.sin(0.5 * p[2]), math.cos(0.5 * p[2])
            transforms.append(t)
        self.tf.sendTransform(transforms)
        m = Odometry()
        m.header.stamp, m.header.frame_id, m.child_frame_id = now, self.ns + "/odom", self.ns + "/base_link"
        m.pose.pose.position.x, m.pose.pose.position.y = odom[0], odom[1]
        m.pose.pose.orientation = transforms[1].transform.rotation
        m.twist.twist.linear.x, m.twist.twist.angular.z = v, w
        self.odom_pub.publish(m)
        s = SurfaceState(sensors=["front_left", "front_right", "mid_left", "mid_right"], front=front, wheels=wheels)
        s.header.stamp = now
        s.surfaces = [front, front, wheels, wheels]
        s.ranges = [RANGES.get(x, float("nan")) for x in s.surfaces]
        self.surface_pub.publish(s)
        _, r = self.nearest_rails(pose)
        if detect:
            # The camera sees the start of the rails 0.65 to 3 m ahead; nearer, only their line (x unobserved).
            d = RailDetectionStatus(status=RailDetectionStatus.NOT_FOUND, reason="no rail pair")
            bearing = math.remainder(math.atan2(-r[1], -r[0]) - r[2], math.tau)
            if -3.0 < r[0] < 0.0 and abs(bearing) < 0.5 and abs(r[1]) < 0.6:
                d = RailDetectionStatus(x=r[0], y=r[1], yaw=r[2], reason="", fit_score=0.99)
                d.status = RailDetectionStatus.FOUND if r[0] < -0.65 else RailDetectionStatus.FOUND_X_UNOBSERVED
            d.header.stamp = now
            self.rail_pub.publish(d)
        if scan:
            # The far wall across the rails' end, seen from the lidar.
            m = LaserScan(angle_min=-0.3, angle_max=0.3, angle_increment=0.01, range_min=0.1, range_max=30.0)
            m.header.stamp, m.header.frame_id = now, self.ns + "/laser"
            to_wall = RAIL_LENGTH + WALL_GAP - r[0] - LIDAR_X * math.cos(r[2])
            cosines = [math.cos(r[2] + m.angle_min + i * m.angle_increment) for i in range(61)]
            m.ranges = [to_wall / c if c > 0.2 and 0.0 < to_wall / c < m.range_max else math.inf for c in cosines]
            self.scan_pub.publish(m)

    def run(self):
        last = time.monotonic()
        i = 0
        rate = rospy.Rate(RATE_HZ)
        while self.running and not rospy.is_shutdown():
            t = time.monotonic()
            self.step(min(t - last, 0.1))
            last = t
            try:
                self.publish(rospy.Time.now(), i % 3 == 0, i % 2 == 0)  # the detector at 17 Hz, the lidar at 25 Hz
                rate.sleep()
            except rospy.ROSException:  # shutting down
                return
            i += 1

    def start(self):
        """Starts the world and waits until the node is connected to it."""
        self.running = True
        threading.Thread(target=self.run, daemon=True).start()
        self.start_srv.wait_for_service(timeout=30.0)
        wait_for(lambda: self.odom_pub.get_num_connections() > 0 and self.surface_pub.get_num_connections() > 0,
                 10.0, "uv_mission in %s subscribing to the world" % self.ns)

    def stop(self):
        self.running = False

    # The mission.
    def start_mission(self):
        def started():
            res = self.start_srv()
            return res.success or res.message != "already running"  # until the last run's thread has finished

        wait_for(started, 5.0, "~start accepted")

    def last_status(self):
        return self.status.last() or MachineStatus()

    def wait_outcome(self, outcome, timeout):
        def ended():
            s = self.status.last()
            return s is not None and not s.running and s.last_outcome == outcome

        try:
            wait_for(ended, timeout, "the mission in %s to end '%s'" % (self.ns, outcome))
        except AssertionError as e:
            s = self.last_status()
            history = ["%s -(%s)-> %s" % (h.state, h.outcome, h.next) for h in s.history]
            raise AssertionError("%s; now in '%s', last transitions: %s" % (e, s.active_state, history))

    def report_rows(self, runs):
        """The rows of mission/report, by rail set, once the node has published it after `runs` runs."""
        msg = self.report.wait_count(runs)
        return {int(r["rail_set"]): r for r in csv.DictReader(io.StringIO(msg.data))}

    def goal_sets(self):
        return [g[0] for g in self.goals]


class UvMissionNode(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.treat = World("treat", rospy.get_param("~treat_rail_sets_file"))
        cls.faults = World("faults", rospy.get_param("~faults_rail_sets_file"))

    @classmethod
    def tearDownClass(cls):
        cls.treat.stop()
        cls.faults.stop()

    def assert_stopped_since(self, world, n, what):
        """The node commanded zero twist after the `n`-th nav_vel message, and nothing else since."""
        later = list(world.twists[n:])
        first = next((i for i, t in enumerate(later) if t == (0.0, 0.0)), None)
        self.assertIsNotNone(first, "no zero twist on nav_vel after %s" % what)
        self.assertEqual([t for t in later[first:] if t != (0.0, 0.0)], [], "moving after %s" % what)

    def assert_lights_only_on_rails(self, world, treated):
        self.assertEqual(world.lights_off_rails[:3], [], "lights on with the wheels off the rails")
        was_on = False
        for on, pose, wheels in world.lights_msgs:
            if on or was_on:  # switched on, or off after being on (the first message is the node's latched off)
                self.assertEqual(wheels, SurfaceState.RAIL, "uv_lights %s at %r, wheels not on rails" % (on, pose))
            was_on = on
        on_sets = {world.nearest_rails(pose)[0] for on, pose, _ in world.lights_msgs if on}
        self.assertEqual(on_sets, treated, "rail sets where the lights went on")
        self.assertFalse(world.lights, "the lights are off at the end")

    def assert_goals_at_targets(self, world):
        """Every move_base goal is a rail set's target pose, in the map frame."""
        for index, pose, frame in world.goals:
            self.assertEqual(frame, world.map_frame)
            self.assertIsNotNone(index, "a goal at no rail set's target pose: %r" % (pose,))
            self.assertAlmostEqual(math.remainder(pose[2] - world.targets[index][2], math.tau), 0.0, places=5)

    def assert_localisation_reset_at(self, world, sets):
        """After each treated set the node gives the pose stored before entering (the map pose move_base left)."""
        self.assertEqual(len(world.initial_poses), len(sets))
        for m, index in zip(world.initial_poses, sets):
            self.assertEqual(m.header.frame_id, world.map_frame)
            expected = compose(world.targets[index], NAV_ERROR)
            self.assertLess(math.dist(pose_of(m.pose.pose)[:2], expected[:2]), 0.03, "initialpose of set %d" % index)

    def test_1_treats_every_good_rail_set(self):
        w = self.treat
        w.start()
        w.start_mission()
        w.wait_outcome("done", 60.0)
        w.stop()
        rows = w.report_rows(1)
        self.assertEqual(sorted(rows), [0, 1, 2])
        for i in (0, 1):
            self.assertEqual((rows[i]["treated"], rows[i]["result"]), ("1", "treated"), "rail set %d" % i)
            self.assertGreater(float(rows[i]["rail_length_m"]), 1.0)
            self.assertGreater(float(rows[i]["lights_on_s"]), 1.0)
            self.assertAlmostEqual(float(rows[i]["speed_mean_mps"]), 0.5, delta=0.08)
        self.assertEqual(rows[2]["treated"], "0")
        self.assertIn("marked uncertain by the map analyzer: a rail end is not seen", rows[2]["result"])
        self.assertEqual(w.goal_sets(), [0, 1], "one move_base goal per good rail set")
        self.assert_goals_at_targets(w)
        self.assert_lights_only_on_rails(w, {0, 1})
        self.assert_localisation_reset_at(w, [0, 1])
        self.assertEqual(w.twists[-1], (0.0, 0.0))

    def test_2_stop_preempts_and_start_resumes(self):
        w = self.faults
        w.abort_sets = {1}
        w.start()
        w.start_mission()
        wait_for(lambda: w.lights and w.in_rails()[0] == 0 and w.in_rails()[1][0] > 0.3, 30.0,
                 "the treatment of rail set 0")
        n = len(w.twists)
        res = w.stop_srv()
        self.assertTrue(res.success, res.message)
        self.assertIn("stopping", res.message)
        w.wait_outcome("preempted", 5.0)
        wait_for(lambda: not w.lights and w.still_for() > 0.5, 5.0, "lights off and the robot standing")
        self.assert_stopped_since(w, n, "~stop")
        self.assertEqual(w.report_rows(1), {}, "no rail set reported before the end of its treatment")
        goals = len(w.goals)
        w.start_mission()
        wait_for(lambda: len(w.goals) > goals, 10.0, "a move_base goal after ~start")
        self.assertEqual(w.goals[goals][0], 0, "~start resumes at the first rail set not treated")
        self.assertEqual(w.goal_wheels[goals], SurfaceState.FLOOR, "the goal after ~start sent from the floor")
        wait_for(lambda: len(w.initial_poses) >= 1, 2.0, "the localisation given the stored pose after reversing")
        self.assertEqual(len(w.initial_poses), 1)
        wait_for(lambda: 1 in w.goal_sets(), 30.0, "set 0 treated and the mission going on")

    def test_3_bumper_lock_pauses_the_motion(self):
        w = self.faults
        wait_for(lambda: w.lights and w.in_rails()[0] == 2 and w.in_rails()[1][0] > 0.3, 30.0,
                 "the treatment of rail set 2")
        n = len(w.twists)
        w.bumper_pub.publish(True)
        try:
            wait_for(lambda: not w.lights and w.still_for() > 1.0, 5.0, "lights off and the robot standing 1 s")
            self.assert_stopped_since(w, n, "the bumper's lock")
            self.assertTrue(w.last_status().running, "paused, not ended")
        finally:
            w.bumper_pub.publish(False)  # a person clears the lock
        wait_for(lambda: w.lights and w.v > 0.1, 5.0, "the treatment going on with the lights on")

    def test_4_aborted_goal_skips_the_set_and_the_mission_goes_on(self):
        w = self.faults
        w.wait_outcome("done", 30.0)
        w.stop()
        rows = w.report_rows(2)
        self.assertEqual(sorted(rows), [0, 1, 2])
        self.assertEqual((rows[0]["treated"], rows[0]["result"]), ("1", "treated"))
        self.assertEqual(rows[1]["treated"], "0")
        self.assertIn("navigation to the target pose failed", rows[1]["result"])
        self.assertEqual((rows[2]["treated"], rows[2]["result"]), ("1", "treated"))
        # Set 0 before ~stop and after ~start, both of the mission's attempts at set 1, then set 2.
        self.assertEqual(w.goal_sets(), [0, 0, 1, 1, 2])
        self.assert_goals_at_targets(w)
        self.assert_lights_only_on_rails(w, {0, 2})
        # Back at set 0's stored pose after ~start (the run stopped on its rails), then after sets 0 and 2.
        self.assert_localisation_reset_at(w, [0, 0, 2])
        self.assertEqual(w.twists[-1], (0.0, 0.0))


if __name__ == "__main__":
    rospy.init_node("uv_mission_node_test")
    rostest.rosrun("greenhouse_rail_nav", "uv_mission_node", UvMissionNode, sys.argv)
