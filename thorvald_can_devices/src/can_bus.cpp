#include "thorvald_can_devices/can_bus.h"

#include "thorvald_can_devices/socket_can_bus.h"
#include "thorvald_can_devices/virtual_can_bus.h"

namespace thorvald_can_devices {

std::unique_ptr<CanBus> openCanBus(const std::string& type, const std::string& name) {
  if (type == "socketcan") return std::make_unique<SocketCanBus>(name);
  if (type == "virtual") return std::make_unique<VirtualCanBus>(name);
  throw CanBusError("can_interface_type must be 'socketcan' or 'virtual', found '" + type + "'");
}

}  // namespace thorvald_can_devices
