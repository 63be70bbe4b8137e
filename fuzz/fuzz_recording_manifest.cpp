// libFuzzer target: the manifest of a recording directory
// (io::parse_manifest), which every command reading a `cubecal record`
// directory parses, whatever a crash, a disk or a hand edit left in it.
// Text that is not a manifest must be a one-line InputError, never another
// exception; a manifest that loads must write out (manifest_text) and
// load again to the same manifest.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "cubecal/io/recording_manifest.hpp"
#include "error_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace cubecal;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  fuzz::expect_clean([&] {
    const io::RecordingManifest m = io::parse_manifest(text, "manifest.json");
    const std::string once = io::manifest_text(m);
    std::string twice;
    try {
      twice = io::manifest_text(io::parse_manifest(once, "manifest.json (written back)"));
    } catch (const InputError& e) {
      fuzz::finding("a loaded manifest does not load again after manifest_text", e.what());
    }
    if (once != twice) fuzz::finding("manifest", "written back, it loads as another manifest");
  });
  return 0;
}
