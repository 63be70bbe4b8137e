#include <string>

#include "commands.hpp"

namespace cubecal::cli {

namespace {
std::string g_invocation;

std::string quote(const std::string& a) {
  if (!a.empty() && a.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-_./:=,+") ==
                        std::string::npos)
    return a;
  std::string q = "'";
  for (char c : a) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}
}  // namespace

const std::string& invocation() { return g_invocation; }

void set_invocation(int argc, char** argv) {
  g_invocation = "cubecal";
  for (int i = 1; i < argc; ++i) g_invocation += " " + quote(argv[i]);
}

}  // namespace cubecal::cli
