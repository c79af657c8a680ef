#include "thorvald_common/ros/bounded_param_read.h"

#include <fcntl.h>
#include <netdb.h>
#include <poll.h>
#include <ros/init.h>
#include <ros/master.h>
#include <ros/this_node.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <memory>

namespace thorvald_common {
namespace {

/// How long a read may wait for the master at most [s]; it is also stopped at once by a shutdown.
constexpr double kMasterTimeout_s = 60.0;
/// Headers and the three-value envelope (code, status text, value) of a reply: allowed beyond the bounds.
constexpr size_t kEnvelopeBytes = 4096;

bool stopRequested() { return ros::isInitialized() && (ros::isShuttingDown() || !ros::ok()); }

/// A socket closed when it goes out of scope.
class Socket {
 public:
  explicit Socket(int fd) : fd_(fd) {}
  ~Socket() {
    if (fd_ >= 0) ::close(fd_);
  }
  Socket(const Socket&) = delete;
  Socket& operator=(const Socket&) = delete;
  int fd() const { return fd_; }
  int release() {
    const int fd = fd_;
    fd_ = -1;
    return fd;
  }

 private:
  int fd_;
};

using Clock = std::chrono::steady_clock;

/// Waits until `fd` is ready for `events`, polling for a shutdown every 100 ms. Throws on a shutdown or a timeout.
void waitFor(int fd, short events, Clock::time_point deadline, const std::string& what) {
  while (true) {
    if (stopRequested()) throw ParamReadInterrupted("reading " + what + " interrupted: the node is shutting down");
    if (Clock::now() > deadline) throw std::runtime_error("the ROS master did not answer " + what + " in time");
    pollfd p{fd, events, 0};
    const int n = ::poll(&p, 1, 100);
    if (n > 0) return;
    if (n < 0 && errno != EINTR) throw std::runtime_error(what + ": poll failed: " + std::strerror(errno));
  }
}

int connectToMaster(Clock::time_point deadline, const std::string& what) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* list = nullptr;
  const std::string host = ros::master::getHost();
  const std::string port = std::to_string(ros::master::getPort());
  if (::getaddrinfo(host.c_str(), port.c_str(), &hints, &list) != 0 || !list) {
    throw std::runtime_error("cannot resolve the ROS master's host '" + host + "'");
  }
  const std::unique_ptr<addrinfo, void (*)(addrinfo*)> found(list, ::freeaddrinfo);
  std::string error = "no address";
  for (const addrinfo* a = found.get(); a; a = a->ai_next) {
    Socket s(::socket(a->ai_family, a->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, a->ai_protocol));
    if (s.fd() < 0) continue;
    if (::connect(s.fd(), a->ai_addr, a->ai_addrlen) != 0 && errno != EINPROGRESS) {
      error = std::strerror(errno);
      continue;
    }
    waitFor(s.fd(), POLLOUT, deadline, what);
    int so_error = 0;
    socklen_t len = sizeof(so_error);
    ::getsockopt(s.fd(), SOL_SOCKET, SO_ERROR, &so_error, &len);
    if (so_error == 0) return s.release();
    error = std::strerror(so_error);
  }
  throw std::runtime_error("cannot connect to the ROS master at " + host + ":" + port + ": " + error);
}

std::string escapeXml(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '<') {
      out += "&lt;";
    } else if (c == '>') {
      out += "&gt;";
    } else if (c == '&') {
      out += "&amp;";
    } else {
      out += c;
    }
  }
  return out;
}

/// Length announced in an HTTP header block, or npos.
size_t contentLength(const std::string& header) {
  std::string lower = header;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const size_t pos = lower.find("content-length:");
  if (pos == std::string::npos) return std::string::npos;
  return std::strtoull(lower.c_str() + pos + 15, nullptr, 10);
}

/// Calls `method` of the master with string arguments and returns the reply's XML, at most `max_bytes` of it
/// (beyond: ParamTooLarge). Stoppable by a shutdown.
std::string callMaster(const std::string& method, const std::vector<std::string>& args, size_t max_bytes,
                       size_t reported_bytes, const std::string& what) {
  const auto deadline =
      Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(kMasterTimeout_s));
  std::string body = "<?xml version=\"1.0\"?><methodCall><methodName>" + method + "</methodName><params>";
  for (const auto& a : args) body += "<param><value><string>" + escapeXml(a) + "</string></value></param>";
  body += "</params></methodCall>";
  const std::string request = "POST /RPC2 HTTP/1.0\r\nUser-Agent: thorvald_common\r\nHost: " + ros::master::getHost() +
                              "\r\nContent-Type: text/xml\r\nContent-length: " + std::to_string(body.size()) +
                              "\r\n\r\n" + body;
  Socket s(connectToMaster(deadline, what));
  for (size_t sent = 0; sent < request.size();) {
    waitFor(s.fd(), POLLOUT, deadline, what);
    const ssize_t n = ::send(s.fd(), request.data() + sent, request.size() - sent, MSG_NOSIGNAL);
    if (n < 0 && errno != EAGAIN && errno != EINTR) throw std::runtime_error(what + ": " + std::strerror(errno));
    if (n > 0) sent += static_cast<size_t>(n);
  }
  std::string reply;
  size_t header_end = std::string::npos, announced = std::string::npos;
  char buffer[65536];
  while (true) {
    waitFor(s.fd(), POLLIN, deadline, what);
    const ssize_t n = ::recv(s.fd(), buffer, sizeof(buffer), 0);
    if (n < 0 && (errno == EAGAIN || errno == EINTR)) continue;
    if (n < 0) throw std::runtime_error(what + ": " + std::strerror(errno));
    if (n == 0) break;
    reply.append(buffer, static_cast<size_t>(n));
    if (header_end == std::string::npos && (header_end = reply.find("\r\n\r\n")) != std::string::npos) {
      announced = contentLength(reply.substr(0, header_end));
      if (announced != std::string::npos && announced > max_bytes) {
        throw ParamTooLarge("takes more than " + std::to_string(reported_bytes) + " bytes (" +
                            std::to_string(announced) + " XML-RPC encoded)");
      }
    }
    const size_t body_bytes = header_end == std::string::npos ? reply.size() : reply.size() - header_end - 4;
    if (body_bytes > max_bytes) throw ParamTooLarge("takes more than " + std::to_string(reported_bytes) + " bytes");
    if (announced != std::string::npos && body_bytes >= announced) break;
  }
  if (header_end == std::string::npos) throw std::runtime_error(what + ": the ROS master sent no complete reply");
  return reply.substr(header_end + 4);
}

/// The value of a master reply [code, status, value]; false when the code is not 1 (e.g. no such parameter).
bool replyValue(const std::string& xml, XmlRpc::XmlRpcValue& value, const std::string& what) {
  if (xml.find("<fault>") != std::string::npos) throw std::runtime_error(what + ": the ROS master answered a fault");
  const size_t param = xml.find("<param>");
  if (param == std::string::npos) throw std::runtime_error(what + ": the ROS master's reply holds no value");
  int offset = static_cast<int>(param + 7);
  XmlRpc::XmlRpcValue triple;
  if (!triple.fromXml(xml, &offset) || triple.getType() != XmlRpc::XmlRpcValue::TypeArray || triple.size() != 3 ||
      triple[0].getType() != XmlRpc::XmlRpcValue::TypeInt) {
    throw std::runtime_error(what + ": the ROS master's reply is malformed");
  }
  if (static_cast<int>(triple[0]) != 1) return false;
  value = triple[2];
  return true;
}

}  // namespace

XmlRpcBound exceededBound(const std::string& xml, size_t max_values, size_t max_depth) {
  size_t values = 0, depth = 0;
  for (size_t pos = xml.find('<'); pos != std::string::npos; pos = xml.find('<', pos + 1)) {
    const size_t end = xml.find_first_of("> \t\r\n/", pos + 2);
    const std::string tag = xml.substr(pos + 1, end == std::string::npos ? std::string::npos : end - pos - 1);
    if (tag == "value") {
      if (++values > max_values) return XmlRpcBound::kValues;
    } else if (tag == "array" || tag == "struct") {
      if (++depth > max_depth) return XmlRpcBound::kDepth;
    } else if ((tag == "/array" || tag == "/struct") && depth > 0) {
      --depth;
    }
  }
  return XmlRpcBound::kNone;
}

bool getParamBounded(const std::string& key, XmlRpc::XmlRpcValue& value, const ParamReadBounds& bounds) {
  const std::string what = "parameter " + key;
  const std::string xml = callMaster("getParam", {ros::this_node::getName(), key}, bounds.max_bytes + kEnvelopeBytes,
                                     bounds.max_bytes, what);
  // The envelope adds four values (the outer one, code, status, the parameter's) and one level of nesting.
  switch (exceededBound(xml, bounds.max_values + 4, bounds.max_depth + 1)) {
    case XmlRpcBound::kValues:
      throw ParamTooLarge("expands to more than " + std::to_string(bounds.max_values) + " values");
    case XmlRpcBound::kDepth:
      throw ParamTooLarge("nests deeper than " + std::to_string(bounds.max_depth) + " levels");
    case XmlRpcBound::kNone:
      break;
  }
  return replyValue(xml, value, what);
}

std::optional<std::vector<std::string>> getParamNamesBounded(size_t max_bytes) {
  std::string xml;
  try {
    xml = callMaster("getParamNames", {ros::this_node::getName()}, max_bytes, max_bytes, "the list of parameter names");
  } catch (const ParamTooLarge&) {
    return std::nullopt;
  }
  XmlRpc::XmlRpcValue names;
  if (!replyValue(xml, names, "the list of parameter names") || names.getType() != XmlRpc::XmlRpcValue::TypeArray) {
    throw std::runtime_error("the ROS master's list of parameter names is malformed");
  }
  std::vector<std::string> out;
  for (int i = 0; i < names.size(); ++i) {
    if (names[i].getType() == XmlRpc::XmlRpcValue::TypeString) out.push_back(static_cast<std::string>(names[i]));
  }
  return out;
}

}  // namespace thorvald_common
