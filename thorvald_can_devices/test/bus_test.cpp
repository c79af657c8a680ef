// The virtual bus (in one process and across processes), error frames on it, and SocketCAN's refusal path.
#include <gtest/gtest.h>

#include <errno.h>
#include <sys/fsuid.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <fstream>
#include <string>

#include "thorvald_can_devices/bus_error.h"
#include "thorvald_can_devices/candump_log.h"
#include "thorvald_can_devices/socket_can_bus.h"
#include "thorvald_can_devices/virtual_can_bus.h"

using namespace thorvald_can_devices;

namespace {

std::string uniqueBus(const std::string& what) { return "t" + std::to_string(::getpid()) + "_" + what; }

bool receiveWithin(CanBus& bus, CanFrame* f, double timeout_s) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < end) {
    if (bus.receive(f)) return true;
    bus.waitReadable(0.01);
  }
  return bus.receive(f);
}

TEST(VirtualBus, EveryOtherEndpointSeesAFrameButNotTheSender) {
  const std::string name = uniqueBus("fanout");
  VirtualCanBus a(name), b(name), c(name);
  const CanFrame f = makeFrame(0x123, {1, 2, 3});
  ASSERT_TRUE(a.send(f));
  CanFrame got;
  ASSERT_TRUE(receiveWithin(b, &got, 1.0));
  EXPECT_EQ(got, f);
  ASSERT_TRUE(receiveWithin(c, &got, 1.0));
  EXPECT_EQ(got, f);
  EXPECT_FALSE(a.receive(&got));
  EXPECT_EQ(a.peerCount(), 2u);
}

TEST(VirtualBus, KeepsOrderAndBoundariesOfManyFrames) {
  const std::string name = uniqueBus("order");
  VirtualCanBus a(name), b(name);
  for (int i = 0; i < 200; ++i) ASSERT_TRUE(a.send(makeFrame(0x100 + (i % 8), {uint8_t(i), uint8_t(i >> 8)})));
  for (int i = 0; i < 200; ++i) {
    CanFrame got;
    ASSERT_TRUE(receiveWithin(b, &got, 1.0)) << i;
    EXPECT_EQ(got, makeFrame(0x100 + (i % 8), {uint8_t(i), uint8_t(i >> 8)}));
  }
}

TEST(VirtualBus, AcrossProcesses) {
  const std::string name = uniqueBus("fork");
  VirtualCanBus parent(name);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    // The child echoes 50 frames with id + 1 and exits.
    int code = 1;
    {
      VirtualCanBus bus(name);
      bus.send(makeFrame(0x7E0, {}));  // hello: the parent now knows the child listens
      int echoed = 0;
      CanFrame f;
      while (echoed < 50 && receiveWithin(bus, &f, 2.0)) {
        f.id += 1;
        bus.send(f);
        ++echoed;
      }
      code = echoed == 50 ? 0 : 2;
    }
    ::_exit(code);
  }
  CanFrame f;
  ASSERT_TRUE(receiveWithin(parent, &f, 5.0));
  EXPECT_EQ(f.id, 0x7E0u);
  for (int i = 0; i < 50; ++i) {
    ASSERT_TRUE(parent.send(makeFrame(0x300, {uint8_t(i), 0xAA, 0x55, 0, 0, 0, 0, uint8_t(255 - i)})));
    ASSERT_TRUE(receiveWithin(parent, &f, 2.0));
    EXPECT_EQ(f, makeFrame(0x301, {uint8_t(i), 0xAA, 0x55, 0, 0, 0, 0, uint8_t(255 - i)}));
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
}

TEST(VirtualBus, ErrorFramesChangeTheBusStateAndAreNotDelivered) {
  const std::string name = uniqueBus("errors");
  VirtualCanBus sim(name), host(name);
  sim.send(makeBusOffFrame());
  sim.send(makeFrame(0x181, {1}));
  CanFrame f;
  ASSERT_TRUE(receiveWithin(host, &f, 1.0));
  EXPECT_EQ(f.id, 0x181u);  // the error frame was consumed by the status
  EXPECT_TRUE(host.status().bus_off);
  EXPECT_FALSE(host.status().ok);
  EXPECT_EQ(host.status().error_frames, 1u);
  sim.send(makeRestartedFrame());
  sim.send(makeFrame(0x182, {1}));
  ASSERT_TRUE(receiveWithin(host, &f, 1.0));
  EXPECT_TRUE(host.status().ok);
  EXPECT_EQ(host.status().last_error, "controller restarted");
}

TEST(VirtualBus, MalformedRecordsAreCountedAndSkipped) {
  const std::string name = uniqueBus("malformed");
  VirtualCanBus host(name), other(name);
  // A raw 5-byte datagram straight to the host's endpoint, then a good frame.
  const int fd = ::socket(AF_UNIX, SOCK_SEQPACKET, 0);
  ASSERT_GE(fd, 0);
  sockaddr_un a{};
  a.sun_family = AF_UNIX;
  std::strncpy(a.sun_path, host.endpointPath().c_str(), sizeof(a.sun_path) - 1);
  ASSERT_EQ(::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof(a)), 0);
  const unsigned char junk[5] = {1, 2, 3, 4, 5};
  ASSERT_EQ(::send(fd, junk, sizeof(junk), 0), 5);
  other.send(makeFrame(0x100, {}));
  CanFrame f;
  ASSERT_TRUE(receiveWithin(host, &f, 1.0));
  EXPECT_EQ(f, makeFrame(0x100, {}));
  EXPECT_FALSE(host.receive(&f));  // reads (and skips) the junk record too
  EXPECT_EQ(host.status().malformed, 1u);
  ::close(fd);
  unsigned char rec[16];
  encodeRecord(makeFrame(0x7FF, {9, 8, 7, 6, 5, 4, 3, 2}), rec);
  CanFrame g;
  EXPECT_TRUE(decodeRecord(rec, 16, &g));
  EXPECT_EQ(g, makeFrame(0x7FF, {9, 8, 7, 6, 5, 4, 3, 2}));
  EXPECT_FALSE(decodeRecord(rec, 15, &g));
  rec[4] = 9;
  EXPECT_FALSE(decodeRecord(rec, 16, &g));
}

TEST(VirtualBus, RemovesEndpointsOfDeadProcesses) {
  const std::string name = uniqueBus("stale");
  VirtualCanBus a(name);
  // An endpoint file nobody listens on, as a crashed process leaves it.
  const std::string stale = VirtualCanBus::busFolder(name) + "/999999-0";
  {
    const int fd = ::socket(AF_UNIX, SOCK_DGRAM, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    std::strncpy(addr.sun_path, stale.c_str(), sizeof(addr.sun_path) - 1);
    ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)), 0);
    ::close(fd);
  }
  ASSERT_EQ(::access(stale.c_str(), F_OK), 0);
  EXPECT_TRUE(a.send(makeFrame(0x100, {})));    // finds the new file, nobody answers the connection
  EXPECT_NE(::access(stale.c_str(), F_OK), 0);  // removed
  EXPECT_EQ(a.peerCount(), 0u);
}

TEST(VirtualBus, RefusesBadNames) {
  EXPECT_THROW(VirtualCanBus(""), CanBusError);
  EXPECT_THROW(VirtualCanBus("../etc"), CanBusError);
  EXPECT_THROW(VirtualCanBus(std::string(49, 'a')), CanBusError);
  EXPECT_THROW(openCanBus("vcan", "x"), CanBusError);
}

bool throwsWith(const std::string& name, const std::string& needle, std::string* what) {
  try {
    VirtualCanBus bus(name);
  } catch (const CanBusError& e) {
    *what = e.what();
    return std::string(e.what()).find(needle) != std::string::npos;
  }
  *what = "no error";
  return false;
}

TEST(VirtualBusSecurity, RefusesABusFolderThatIsASymlinkAndTouchesNothingBehindIt) {
  const std::string name = uniqueBus("symlink");
  char target[] = "/tmp/thorvald_can_target.XXXXXX";
  ASSERT_NE(::mkdtemp(target), nullptr);
  const std::string victim = std::string(target) + "/123-0";  // named like an endpoint, a plain file
  std::ofstream(victim) << "keep me";
  ::close(openPrivateFolder(VirtualCanBus::rootFolder()));
  ASSERT_EQ(::symlink(target, VirtualCanBus::busFolder(name).c_str()), 0);
  std::string what;
  EXPECT_TRUE(throwsWith(name, "symbolic link", &what)) << what;
  EXPECT_NE(what.find(VirtualCanBus::busFolder(name)), std::string::npos) << what;
  EXPECT_EQ(::access(victim.c_str(), F_OK), 0);
  ::unlink(VirtualCanBus::busFolder(name).c_str());
  ::unlink(victim.c_str());
  ::rmdir(target);
}

TEST(VirtualBusSecurity, RefusesAFolderWritableByOthers) {
  const std::string name = uniqueBus("mode");
  ::close(openPrivateFolder(VirtualCanBus::rootFolder()));
  const std::string folder = VirtualCanBus::busFolder(name);
  ASSERT_EQ(::mkdir(folder.c_str(), 0700), 0);
  ASSERT_EQ(::chmod(folder.c_str(), 0777), 0);
  std::string what;
  EXPECT_TRUE(throwsWith(name, "mode 0777", &what)) << what;
  ASSERT_EQ(::chmod(folder.c_str(), 0730), 0);
  EXPECT_TRUE(throwsWith(name, "group or others write", &what)) << what;
  ASSERT_EQ(::chmod(folder.c_str(), 0700), 0);
  EXPECT_NO_THROW(VirtualCanBus bus(name));
  ::rmdir(folder.c_str());
}

TEST(VirtualBusSecurity, RefusesAFolderOfAnotherUser) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to give a folder to another user";
  const std::string name = uniqueBus("owner");
  ::close(openPrivateFolder(VirtualCanBus::rootFolder()));
  const std::string folder = VirtualCanBus::busFolder(name);
  ASSERT_EQ(::mkdir(folder.c_str(), 0700), 0);
  ASSERT_EQ(::chown(folder.c_str(), 65534, 65534), 0);
  std::string what;
  EXPECT_TRUE(throwsWith(name, "belongs to uid 65534", &what)) << what;
  ::rmdir(folder.c_str());
}

TEST(VirtualBusSecurity, NeverRemovesWhatIsNotOneOfItsSockets) {
  const std::string name = uniqueBus("foreignfiles");
  VirtualCanBus a(name);
  const std::string folder = VirtualCanBus::busFolder(name);
  const std::string plain = folder + "/4242-0";  // endpoint name, but a plain file
  std::ofstream(plain) << "x";
  const std::string other_socket = folder + "/not-an-endpoint";  // a socket nobody listens on, other name
  {
    const int fd = ::socket(AF_UNIX, SOCK_SEQPACKET, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    std::strncpy(addr.sun_path, other_socket.c_str(), sizeof(addr.sun_path) - 1);
    ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)), 0);
    ::close(fd);
  }
  EXPECT_TRUE(a.send(makeFrame(0x100, {})));
  EXPECT_EQ(a.peerCount(), 0u);
  EXPECT_EQ(::access(plain.c_str(), F_OK), 0);
  EXPECT_EQ(::access(other_socket.c_str(), F_OK), 0);
  ::unlink(plain.c_str());
  ::unlink(other_socket.c_str());
}

TEST(VirtualBusSecurity, RefusesConnectionsFromAnotherUser) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to connect as another user";
  const std::string name = uniqueBus("peercred");
  VirtualCanBus host(name);
  const std::string path = host.endpointPath();
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    // Another user (euid 65534) that can still reach the socket file (fsuid 0): only SO_PEERCRED stops it.
    if (::setegid(65534) != 0 || ::seteuid(65534) != 0) ::_exit(3);
    ::setfsuid(0);
    const int fd = ::socket(AF_UNIX, SOCK_SEQPACKET, 0);
    sockaddr_un a{};
    a.sun_family = AF_UNIX;
    std::strncpy(a.sun_path, path.c_str(), sizeof(a.sun_path) - 1);
    if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof(a)) != 0) ::_exit(4);
    unsigned char rec[16];
    encodeRecord(makeFrame(0x000, {0x01, 0x00}), rec);  // NMT start all
    ::send(fd, rec, sizeof(rec), 0);
    ::_exit(0);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  ASSERT_EQ(WEXITSTATUS(status), 0);
  CanFrame f;
  EXPECT_FALSE(receiveWithin(host, &f, 0.2));
  EXPECT_EQ(host.foreignPeersRefused(), 1u);
  EXPECT_NE(host.status().last_error.find("uid 65534"), std::string::npos) << host.status().last_error;
}

TEST(VirtualBusSecurity, CapsEndpointsPerBus) {
  const std::string name = uniqueBus("cap");
  VirtualBusOptions o;
  o.max_endpoints = 3;
  VirtualCanBus a(name, o), b(name, o), c(name, o);
  std::string what;
  try {
    VirtualCanBus d(name, o);
    ADD_FAILURE() << "a fourth endpoint was accepted";
  } catch (const CanBusError& e) {
    what = e.what();
  }
  EXPECT_NE(what.find("already has 3 endpoints"), std::string::npos) << what;
  ASSERT_TRUE(a.send(makeFrame(0x10, {})));
  CanFrame f;
  EXPECT_TRUE(receiveWithin(c, &f, 1.0));
}

TEST(VirtualBusSecurity, LastEndpointRemovesTheBusFolder) {
  const std::string name = uniqueBus("tidy");
  { VirtualCanBus a(name), b(name); }
  EXPECT_NE(::access(VirtualCanBus::busFolder(name).c_str(), F_OK), 0);
}

TEST(SocketCan, SaysClearlyWhenTheKernelRefusesCanSockets) {
  try {
    SocketCanBus bus("thorvaldnone0");
    FAIL() << "an interface that does not exist cannot be opened";
  } catch (const CanBusError& e) {
    if (e.errorNumber() == EAFNOSUPPORT) {
      // This machine: no CAN in the kernel.
      EXPECT_EQ(std::string(e.what()), socketCanUnsupportedMessage("thorvaldnone0"));
      EXPECT_NE(std::string(e.what()).find("EAFNOSUPPORT"), std::string::npos);
      EXPECT_NE(std::string(e.what()).find("virtual"), std::string::npos);
    } else {
      // A kernel with CAN: the interface is missing.
      EXPECT_NE(std::string(e.what()).find("no interface 'thorvaldnone0'"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(openCanBus("socketcan", "can0"), CanBusError);
  EXPECT_THROW(SocketCanBus(""), CanBusError);
}

TEST(Candump, LoggingBusWritesWhatCanplayerReads) {
  const std::string name = uniqueBus("log");
  const std::string path = "/tmp/" + name + ".log";
  ::unlink(path.c_str());
  VirtualCanBus peer(name);
  {
    LoggingCanBus bus(std::make_unique<VirtualCanBus>(name), path, "vcan_" + name);
    bus.send(makeFrame(0x201, {1, 2}));
    peer.send(makeFrame(0x181, {3}));
    CanFrame f;
    ASSERT_TRUE(receiveWithin(bus, &f, 1.0));
  }
  std::ifstream in(path);
  std::string line;
  std::vector<CanFrame> frames;
  while (std::getline(in, line)) {
    double t;
    std::string iface;
    CanFrame f;
    ASSERT_TRUE(parseCandumpLine(line, &t, &iface, &f)) << line;
    EXPECT_EQ(iface, "vcan_" + name);
    frames.push_back(f);
  }
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[0], makeFrame(0x201, {1, 2}));
  EXPECT_EQ(frames[1], makeFrame(0x181, {3}));
  ::unlink(path.c_str());
}

}  // namespace
