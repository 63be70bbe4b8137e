// Choosing a source from the command line's SOURCE (source.hpp).
#include <unistd.h>

#include "cubecal/acquire/source.hpp"
#include "cubecal/error.hpp"

namespace cubecal::acquire {

std::unique_ptr<Source> open_source(const std::string& spec, const SourceOptions& opt) {
  if (spec == "-") return open_fd_source(STDIN_FILENO, "stdin");
  if (spec.rfind("tcp:", 0) == 0) {
    const std::string rest = spec.substr(4);
    const auto colon = rest.rfind(':');
    if (colon == std::string::npos || colon == 0 || colon + 1 == rest.size())
      throw UsageError(Field::source, spec + ": a TCP source is tcp:HOST:PORT (e.g. tcp:192.168.1.20:5000)");
    std::string host = rest.substr(0, colon);
    if (host.size() >= 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
    return open_tcp_source(host, rest.substr(colon + 1), opt);
  }
  if (spec.rfind("udp:", 0) == 0) {
    const std::string port = spec.substr(4);
    if (port.empty()) throw UsageError(Field::source, spec + ": a UDP source is udp:PORT (e.g. udp:5000)");
    return open_udp_source(port);
  }
  return open_serial_source(spec, opt);
}

}  // namespace cubecal::acquire
