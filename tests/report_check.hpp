// Test support for report pages: file and shell helpers, a small PNG decoder,
// and a page loaded in headless Chromium (a screenshot, and the DOM after the
// page's own script marked whether every image decoded).
#pragma once
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace cubecal::test {

std::string slurp(const std::filesystem::path& p);
void spit(const std::filesystem::path& p, const std::string& s);
// Non-overlapping occurrences of needle in hay.
std::size_t count(const std::string& hay, const std::string& needle);

// An executable on PATH, or empty.
std::string on_path(const std::string& name);

std::string shell_quote(const std::string& s);

// chromium, chromium-browser or google-chrome on PATH; empty when none.
std::string find_chromium();

struct PngImage {
  std::uint32_t width = 0, height = 0;
  std::vector<std::uint32_t> rgb;  // 0xRRGGBB per pixel
};

// 8-bit RGB / RGBA, non-interlaced (what Chromium writes); empty otherwise.
PngImage decode_png(const std::string& bytes);

struct BrowserPage {
  std::string error;           // not empty: a Chromium run failed (the command and its output)
  std::filesystem::path shot;  // the screenshot
  std::uintmax_t shot_bytes = 0;
  PngImage image;             // the screenshot decoded
  std::size_t colours = 0;    // distinct colours in it
  double ink_fraction = 0.0;  // share of pixels that are not white
  double seconds = 0.0;       // of the screenshot run
  std::string dom;            // the DOM after the page's scripts ran
};

// `html` in headless Chromium: a width x height screenshot and a DOM dump,
// their files (and Chromium's profiles) in `work` (created).
BrowserPage load_in_chromium(const std::string& chromium, const std::filesystem::path& html,
                             const std::filesystem::path& work, int width = 1200, int height = 2000);

}  // namespace cubecal::test
