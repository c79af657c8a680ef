#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <string>

#include "thorvald_teleop/joystick_device.h"
#include "thorvald_teleop/joystick_state.h"

using namespace thorvald_teleop;

TEST(ScaleAxis, DeadzoneAndSignLikeJoy) {
  EXPECT_DOUBLE_EQ(scaleAxis(0, 0.1), 0.0);
  EXPECT_DOUBLE_EQ(scaleAxis(3276, 0.1), 0.0);  // 3276/32767 < 0.1
  EXPECT_DOUBLE_EQ(scaleAxis(32767, 0.1), -1.0);
  EXPECT_DOUBLE_EQ(scaleAxis(-32767, 0.1), 1.0);
  EXPECT_DOUBLE_EQ(scaleAxis(-32768, 0.1), 1.0);  // clamped
  EXPECT_NEAR(scaleAxis(16384, 0.1), -((16384.0 / 32767.0) - 0.1) / 0.9, 1e-12);
  EXPECT_NEAR(scaleAxis(16384, 0.0), -16384.0 / 32767.0, 1e-12);
}

TEST(JoystickState, AppliesEventsAndGrows) {
  JoystickState s(0.0);
  EXPECT_TRUE(s.apply({0, 1, kJsButton | kJsInit, 3}));
  EXPECT_EQ(s.buttons(), (std::vector<int>{0, 0, 0, 1}));
  EXPECT_FALSE(s.apply({0, 1, kJsButton, 3}));  // unchanged
  EXPECT_TRUE(s.apply({0, -32767, kJsAxis, 1}));
  ASSERT_EQ(s.axes().size(), 2u);
  EXPECT_FLOAT_EQ(s.axes()[1], 1.0f);
  EXPECT_TRUE(s.apply({0, 0, kJsAxis | kJsInit, 2}));  // a new axis at rest is still news
  EXPECT_FALSE(s.apply({0, 5, 0x10, 0}));
  EXPECT_EQ(s.unknownEvents(), 1u);
}

TEST(JoystickDevice, MissingDeviceReportsReason) {
  JoystickDevice d;
  std::string error;
  EXPECT_FALSE(d.open("/nonexistent/js9", error));
  EXPECT_NE(error.find("No such file"), std::string::npos);
}

TEST(JoystickDevice, ReadsEventsFromAFifoAndSeesTheWriterLeave) {
  const std::string path = "/tmp/thorvald_teleop_gtest_fifo_" + std::to_string(getpid());
  ASSERT_EQ(mkfifo(path.c_str(), 0600), 0);
  JoystickDevice d;
  std::string error;
  ASSERT_TRUE(d.open(path, error)) << error;
  const int writer = ::open(path.c_str(), O_WRONLY | O_NONBLOCK);
  ASSERT_GE(writer, 0);
  const JsEvent events[2] = {{10, 1, kJsButton, 2}, {11, -32767, kJsAxis, 0}};
  // Write one and a half events, then the rest: the split event must arrive whole.
  const char* bytes = reinterpret_cast<const char*>(events);
  ASSERT_EQ(write(writer, bytes, 12), 12);
  std::vector<JsEvent> got;
  EXPECT_EQ(d.read(1000, got, error), JoystickDevice::ReadResult::kEvents);
  ASSERT_EQ(got.size(), 1u);
  ASSERT_EQ(write(writer, bytes + 12, 4), 4);
  EXPECT_EQ(d.read(1000, got, error), JoystickDevice::ReadResult::kEvents);
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got[1].value, -32767);
  EXPECT_EQ(got[1].type, kJsAxis);
  close(writer);
  EXPECT_EQ(d.read(1000, got, error), JoystickDevice::ReadResult::kDisconnected);
  unlink(path.c_str());
}
