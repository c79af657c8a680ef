// The NMEA TCP server (a client connects, receives whole sentences, a silent client is dropped, a closed one goes)
// and the log reader's epochs.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>

#include "thorvald_gnss/nmea_line_server.h"
#include "thorvald_gnss/nmea_log.h"

namespace thorvald_gnss {
namespace {

int connectTo(int port) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  inet_pton(AF_INET, "127.0.0.1", &addr.sin_addr);
  EXPECT_EQ(connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)), 0);
  return fd;
}

/// Polls the server until `condition` holds or 2 s pass.
template <typename Condition>
bool pollUntil(NmeaLineServer& server, Condition condition) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (std::chrono::steady_clock::now() < deadline) {
    server.poll();
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return condition();
}

std::string receive(int fd, size_t bytes) {
  std::string text;
  while (text.size() < bytes) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, 2000) <= 0) break;
    char buffer[512];
    const ssize_t n = recv(fd, buffer, sizeof(buffer), 0);
    if (n <= 0) break;
    text.append(buffer, static_cast<size_t>(n));
  }
  return text;
}

TEST(NmeaLineServer, ServesSentencesToEveryClient) {
  NmeaLineServer server("127.0.0.1", 0);
  ASSERT_GT(server.port(), 0);
  const int a = connectTo(server.port());
  const int b = connectTo(server.port());
  ASSERT_TRUE(pollUntil(server, [&] { return server.clients() == 2; }));
  const std::string sentence = "$GNGGA,000000.00,,,,,0,00,99.99,,,,,,*78\r\n";
  server.send(sentence);
  EXPECT_EQ(receive(a, sentence.size()), sentence);
  EXPECT_EQ(receive(b, sentence.size()), sentence);
  ::close(a);
  EXPECT_TRUE(pollUntil(server, [&] { return server.clients() == 1; }));
  ::close(b);
  EXPECT_TRUE(pollUntil(server, [&] { return server.clients() == 0; }));
  EXPECT_EQ(server.accepted(), 2u);
}

TEST(NmeaLineServer, DropsAClientThatDoesNotRead) {
  NmeaLineServer server("127.0.0.1", 0, 8, 4096);
  const int fd = connectTo(server.port());
  ASSERT_TRUE(pollUntil(server, [&] { return server.clients() == 1; }));
  const std::string block(1000, 'x');
  for (int i = 0; i < 10000 && server.clients() > 0; ++i) server.send(block);  // kernel buffers fill, then backlog
  EXPECT_EQ(server.clients(), 0u);
  EXPECT_EQ(server.dropped(), 1u);
  ::close(fd);
}

TEST(NmeaLineServer, NamesTheAddressItCannotUse) {
  EXPECT_THROW(NmeaLineServer("not an address", 10110), std::runtime_error);
  NmeaLineServer first("127.0.0.1", 0);
  try {
    NmeaLineServer second("127.0.0.1", first.port());
    FAIL() << "a second server on the same port";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("127.0.0.1:" + std::to_string(first.port())), std::string::npos) << e.what();
  }
}

TEST(NmeaLog, CutsEpochsAtNewTimes) {
  std::istringstream log(
      "# a comment\n"
      "$GNGGA,000000.00,,,,,0,00,99.99,,,,,,*78\r\n"
      "$GNRMC,000000.00,V,,,,,,,010721,,,N*66\n"
      "\n"
      "$GNGGA,000000.20,,,,,0,00,99.99,,,,,,*7A\r\n"
      "$GPGSV,1,1,00*79\n"
      "garbage\n"
      "$GNRMC,000000.20,V,,,,,,,010721,,,N*64\n");
  size_t rejected = 0;
  const auto epochs = readNmeaEpochs(log, &rejected);
  ASSERT_EQ(epochs.size(), 2u);
  EXPECT_EQ(rejected, 1u);
  EXPECT_EQ(epochs[0].time, "000000.00");
  EXPECT_EQ(epochs[0].text, "$GNGGA,000000.00,,,,,0,00,99.99,,,,,,*78\r\n$GNRMC,000000.00,V,,,,,,,010721,,,N*66\r\n");
  EXPECT_EQ(epochs[1].time, "000000.20");
  EXPECT_NE(epochs[1].text.find("$GPGSV,1,1,00*79\r\n"), std::string::npos);  // a sentence without time joins
}

TEST(NmeaLog, BoundedNumberOfLines) {
  std::istringstream log("$GNGGA,000000.00,,,,,0,00,99.99,,,,,,*78\n$GNGGA,000000.20,,,,,0,00,99.99,,,,,,*7A\n");
  EXPECT_EQ(readNmeaEpochs(log, nullptr, 1).size(), 1u);
}

}  // namespace
}  // namespace thorvald_gnss
