#include "report_check.hpp"

#include <zlib.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <unordered_set>

#include "cubecal/report/plot.hpp"

namespace cubecal::test {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

void spit(const fs::path& p, const std::string& s) {
  std::ofstream f(p, std::ios::binary | std::ios::trunc);
  f << s;
}

std::size_t count(const std::string& hay, const std::string& needle) {
  std::size_t n = 0;
  for (auto p = hay.find(needle); p != std::string::npos; p = hay.find(needle, p + needle.size())) ++n;
  return n;
}

std::string on_path(const std::string& name) {
  const auto p = report::find_gnuplot(name);  // finds any executable by name
  return p ? *p : std::string();
}

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string find_chromium() {
  std::string chromium;
  for (const char* name : {"chromium", "chromium-browser", "google-chrome"})
    if (chromium.empty()) chromium = on_path(name);
  return chromium;
}

namespace {

std::uint32_t be32(const unsigned char* p) {
  return (std::uint32_t(p[0]) << 24) | (std::uint32_t(p[1]) << 16) | (std::uint32_t(p[2]) << 8) | p[3];
}

}  // namespace

PngImage decode_png(const std::string& bytes) {
  PngImage img;
  const auto* b = reinterpret_cast<const unsigned char*>(bytes.data());
  if (bytes.size() < 33 || bytes.compare(1, 3, "PNG") != 0) return img;
  std::string idat;
  int channels = 0;
  for (std::size_t p = 8; p + 12 <= bytes.size();) {
    const std::uint32_t len = be32(b + p);
    const std::string type = bytes.substr(p + 4, 4);
    if (p + 12 + len > bytes.size()) return {};
    if (type == "IHDR") {
      img.width = be32(b + p + 8);
      img.height = be32(b + p + 12);
      const int depth = b[p + 16], color = b[p + 17], interlace = b[p + 20];
      if (depth != 8 || interlace != 0 || (color != 2 && color != 6)) return {};
      channels = color == 2 ? 3 : 4;
    } else if (type == "IDAT") {
      idat.append(bytes, p + 8, len);
    }
    p += 12 + len;
  }
  if (!channels) return {};
  const std::size_t stride = std::size_t(img.width) * channels;
  std::vector<unsigned char> raw((stride + 1) * img.height);
  uLongf n = static_cast<uLongf>(raw.size());
  if (uncompress(raw.data(), &n, reinterpret_cast<const Bytef*>(idat.data()), static_cast<uLong>(idat.size())) !=
          Z_OK ||
      n != raw.size())
    return {};
  std::vector<unsigned char> prev(stride, 0), cur(stride);
  img.rgb.reserve(std::size_t(img.width) * img.height);
  for (std::uint32_t y = 0; y < img.height; ++y) {
    const unsigned char* row = raw.data() + y * (stride + 1);
    const int filter = row[0];
    for (std::size_t i = 0; i < stride; ++i) {
      const int a = i >= std::size_t(channels) ? cur[i - channels] : 0;
      const int up = prev[i];
      const int c = i >= std::size_t(channels) ? prev[i - channels] : 0;
      int pred = 0;
      switch (filter) {
        case 1: pred = a; break;
        case 2: pred = up; break;
        case 3: pred = (a + up) / 2; break;
        case 4: {
          const int pp = a + up - c, pa = std::abs(pp - a), pb = std::abs(pp - up), pc = std::abs(pp - c);
          pred = (pa <= pb && pa <= pc) ? a : (pb <= pc ? up : c);
          break;
        }
        default: break;
      }
      cur[i] = static_cast<unsigned char>(row[1 + i] + pred);
    }
    for (std::uint32_t x = 0; x < img.width; ++x) {
      const unsigned char* px = cur.data() + std::size_t(x) * channels;
      img.rgb.push_back((std::uint32_t(px[0]) << 16) | (std::uint32_t(px[1]) << 8) | px[2]);
    }
    std::swap(prev, cur);
  }
  return img;
}

BrowserPage load_in_chromium(const std::string& chromium, const fs::path& html_in, const fs::path& work, int width,
                             int height) {
  BrowserPage page;
  fs::create_directories(work);
  const fs::path html = fs::absolute(html_in);
  const std::string flags =
      " --headless --no-sandbox --disable-gpu --no-first-run --disable-background-networking"
      " --disable-component-update --disable-sync --hide-scrollbars";
  const std::string url = shell_quote("file://" + html.string());
  const fs::path logf = work / "chromium.log";
  const std::string log = shell_quote(logf.string());
  const std::string timeout = on_path("timeout").empty() ? "" : "timeout 120 ";

  // Screenshot.
  page.shot = work / "shot.png";
  const auto t0 = std::chrono::steady_clock::now();
  const std::string cmd1 =
      timeout + shell_quote(chromium) + flags + " --user-data-dir=" + shell_quote((work / "profile1").string()) +
      " --screenshot=" + shell_quote(page.shot.string()) + " --window-size=" + std::to_string(width) + "," +
      std::to_string(height) + " " + url + " > " + log + " 2>&1";
  const int rc1 = std::system(cmd1.c_str());
  page.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (rc1 != 0 || !fs::exists(page.shot)) {
    page.error = cmd1 + "\n" + slurp(logf);
    return page;
  }
  page.shot_bytes = fs::file_size(page.shot);
  page.image = decode_png(slurp(page.shot));
  const std::unordered_set<std::uint32_t> colours(page.image.rgb.begin(), page.image.rgb.end());
  page.colours = colours.size();
  std::size_t ink = 0;
  for (auto c : page.image.rgb) ink += c != 0xffffffu;
  if (!page.image.rgb.empty())
    page.ink_fraction = static_cast<double>(ink) / static_cast<double>(page.image.rgb.size());

  // The DOM after the page's scripts ran.
  const fs::path dom = work / "dom.html";
  const std::string cmd2 =
      timeout + shell_quote(chromium) + flags + " --user-data-dir=" + shell_quote((work / "profile2").string()) +
      " --virtual-time-budget=5000 --dump-dom " + url + " > " + shell_quote(dom.string()) + " 2> " + log;
  if (std::system(cmd2.c_str()) != 0) {
    page.error = cmd2 + "\n" + slurp(logf);
    return page;
  }
  page.dom = slurp(dom);
  return page;
}

}  // namespace cubecal::test
