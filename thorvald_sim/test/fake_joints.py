#!/usr/bin/python3
"""Stands in for thorvald_sim's physics in tests of SimHardware without MuJoCo: answers on sim/joint_measured with
the joints named in ~joints, each wheel turning at the speed last commanded on sim/joint_commands (steering joints
at their commanded angle), at ~rate Hz."""
import rospy
from sensor_msgs.msg import JointState


def main():
    rospy.init_node("fake_joints")
    names = rospy.get_param("~joints")
    rate = rospy.Rate(rospy.get_param("~rate", 50.0))
    position = {n: 0.0 for n in names}
    velocity = {n: 0.0 for n in names}

    def on_command(msg):
        for i, n in enumerate(msg.name):
            if n in position and i < len(msg.velocity) and i < len(msg.position):
                if n.split("/")[-1].startswith("steering"):
                    position[n] = msg.position[i]
                else:
                    velocity[n] = msg.velocity[i]

    rospy.Subscriber("sim/joint_commands", JointState, on_command, queue_size=20)
    pub = rospy.Publisher("sim/joint_measured", JointState, queue_size=5)
    period = 1.0 / rospy.get_param("~rate", 50.0)
    while not rospy.is_shutdown():
        msg = JointState()
        msg.header.stamp = rospy.Time.now()
        for n in names:
            position[n] += velocity[n] * period
            msg.name.append(n)
            msg.position.append(position[n])
            msg.velocity.append(velocity[n])
        pub.publish(msg)
        try:
            rate.sleep()
        except rospy.ROSInterruptException:
            break


if __name__ == "__main__":
    main()
