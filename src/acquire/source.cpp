// Choosing a source from the command line's SOURCE (source.hpp).
#include <unistd.h>

#include <string>
#include <utility>

#include "cubecal/acquire/source.hpp"
#include "cubecal/error.hpp"
#include "cubecal/printable_text.hpp"

namespace cubecal::acquire {

namespace {

// HOST:PORT split at the last colon, [v6] brackets removed; `port` checked.
std::pair<std::string, std::string> host_and_port(const std::string& spec, const std::string& rest,
                                                  const std::string& form) {
  const auto colon = rest.rfind(':');
  std::string host = colon == std::string::npos ? std::string() : rest.substr(0, colon);
  const std::string port = colon == std::string::npos ? rest : rest.substr(colon + 1);
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
  const bool digits = !port.empty() && port.size() <= 5 && port.find_first_not_of("0123456789") == std::string::npos;
  if (!digits || std::stoi(port) < 1 || std::stoi(port) > 65535)
    throw UsageError(Field::source, printable_text(spec) + ": the port is a number from 1 to 65535 (" + form + ")");
  return {host, port};
}

}  // namespace

std::unique_ptr<Source> open_source(const std::string& spec, const SourceOptions& opt) {
  if (spec == "-") return open_fd_source(STDIN_FILENO, "stdin");
  if (spec.rfind("tcp:", 0) == 0) {
    const std::string rest = spec.substr(4);
    const auto colon = rest.rfind(':');
    if (colon == std::string::npos || colon == 0 || colon + 1 == rest.size())
      throw UsageError(Field::source,
                       printable_text(spec) + ": a TCP source is tcp:HOST:PORT (e.g. tcp:192.168.1.20:5000)");
    const auto [host, port] = host_and_port(spec, rest, "tcp:HOST:PORT, e.g. tcp:192.168.1.20:5000");
    return open_tcp_source(host, port, opt);
  }
  if (spec.rfind("udp:", 0) == 0) {
    const std::string rest = spec.substr(4);
    const auto [address, port] = host_and_port(
        spec, rest, "udp:PORT on 127.0.0.1, udp:ADDRESS:PORT on a local address, udp:0.0.0.0:PORT on all");
    if (rest.find(':') != std::string::npos && address.empty())
      throw UsageError(Field::source, printable_text(spec) +
                                          ": the address before the port is empty (udp:PORT, or "
                                          "udp:ADDRESS:PORT such as udp:0.0.0.0:5000)");
    return open_udp_source(address, port);
  }
  return open_serial_source(spec, opt);
}

}  // namespace cubecal::acquire
