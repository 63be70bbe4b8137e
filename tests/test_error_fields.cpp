// The error types and their fields: one cubecal::Error base, field markers
// that name known fields, and a CLI flag for every field an option sets.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "../src/cli/field_flags.hpp"
#include "cubecal/error.hpp"
#include "cubecal/field.hpp"

namespace {

using cubecal::Field;
namespace fs = std::filesystem;

static_assert(std::is_base_of_v<cubecal::Error, cubecal::UsageError>);
static_assert(std::is_base_of_v<cubecal::Error, cubecal::InputError>);
static_assert(std::is_base_of_v<cubecal::Error, cubecal::CalibrationError>);
static_assert(std::is_base_of_v<std::runtime_error, cubecal::Error>);
static_assert(!std::is_base_of_v<std::invalid_argument, cubecal::UsageError>);
static_assert(!std::is_base_of_v<std::invalid_argument, cubecal::InputError>);
static_assert(!std::is_base_of_v<std::invalid_argument, cubecal::CalibrationError>);

// The string literals of a C++ source, comments and character literals left
// out (no raw strings in the tree).
std::vector<std::string> string_literals(const std::string& src) {
  std::vector<std::string> out;
  std::size_t i = 0;
  while (i < src.size()) {
    if (src.compare(i, 2, "//") == 0) {
      i = src.find('\n', i);
      if (i == std::string::npos) break;
    } else if (src.compare(i, 2, "/*") == 0) {
      i = src.find("*/", i + 2);
      if (i == std::string::npos) break;
      i += 2;
    } else if (src[i] == '\'') {
      ++i;
      while (i < src.size() && src[i] != '\'') i += src[i] == '\\' ? 2 : 1;
      ++i;
    } else if (src[i] == '"') {
      std::string lit;
      ++i;
      while (i < src.size() && src[i] != '"') {
        if (src[i] == '\\' && i + 1 < src.size()) lit += src[i++];
        lit += src[i++];
      }
      ++i;
      out.push_back(std::move(lit));
    } else {
      ++i;
    }
  }
  return out;
}

// `{name}` in `lit` with name a lowercase identifier.
std::vector<std::string> markers_in(const std::string& lit) {
  std::vector<std::string> out;
  for (std::size_t open = lit.find('{'); open != std::string::npos; open = lit.find('{', open + 1)) {
    const std::size_t close = lit.find('}', open + 1);
    if (close == std::string::npos) break;
    const std::string name = lit.substr(open + 1, close - open - 1);
    if (name.empty()) continue;
    bool word = true;
    for (const char c : name) word = word && ((c >= 'a' && c <= 'z') || c == '_');
    if (word) out.push_back(name);
  }
  return out;
}

TEST(ErrorFields, EveryMarkerInALibraryLiteralIsAField) {
  std::size_t found = 0;
  for (const char* dir : {"src", "include"}) {
    for (const auto& entry : fs::recursive_directory_iterator(fs::path(CUBECAL_SOURCE_DIR) / dir)) {
      const auto ext = entry.path().extension();
      if (!entry.is_regular_file() || (ext != ".cpp" && ext != ".hpp")) continue;
      std::ifstream in(entry.path());
      std::stringstream ss;
      ss << in.rdbuf();
      for (const std::string& lit : string_literals(ss.str()))
        for (const std::string& name : markers_in(lit)) {
          ++found;
          EXPECT_TRUE(cubecal::field_from_name(name).has_value())
              << entry.path().string() << ": {" << name << "} names no cubecal::Field";
        }
    }
  }
  EXPECT_GT(found, 50u);  // the scan sees the markers at all
}

TEST(ErrorFields, TheCliHasAFlagForEveryField) {
  // Fields no option of the CLI sets: the record itself, or a setting the
  // CLI fixes. Their errors read as the library words them.
  const std::set<Field> no_option = {Field::exponents, Field::samples, Field::scales, Field::segments, Field::sync};
  for (std::size_t i = 0; i < cubecal::kFieldCount; ++i) {
    const auto f = static_cast<Field>(i);
    const auto flag = cubecal::cli::field_flag(f).flag;
    if (no_option.count(f) != 0) {
      EXPECT_TRUE(flag.empty()) << cubecal::field_name(f);
      continue;
    }
    EXPECT_FALSE(flag.empty()) << cubecal::field_name(f) << " has no CLI flag";
    EXPECT_TRUE(flag.starts_with("--") || flag == "SOURCE") << cubecal::field_name(f) << ": " << flag;
  }
}

TEST(ErrorFields, NamesRoundTrip) {
  std::set<std::string_view> names;
  for (std::size_t i = 0; i < cubecal::kFieldCount; ++i) {
    const auto f = static_cast<Field>(i);
    EXPECT_EQ(cubecal::field_from_name(cubecal::field_name(f)), f);
    EXPECT_TRUE(names.insert(cubecal::field_name(f)).second) << cubecal::field_name(f);
  }
  EXPECT_FALSE(cubecal::field_from_name("no_such_field").has_value());
}

TEST(ErrorFields, MarkersRenderInEachFacesWords) {
  const std::string text = "leave out {stream}, or {gaps} skip; {x} and {} stay";
  EXPECT_EQ(cubecal::library_words(text), "leave out stream, or gaps skip; {x} and {} stay");
  EXPECT_EQ(cubecal::cli::flag_words(text), "leave out --stream, or --gaps skip; {x} and {} stay");
  EXPECT_EQ(cubecal::marker(Field::stream), "{stream}");
}

TEST(ErrorFields, AnErrorKeepsItsMarkersForTheFace) {
  const cubecal::UsageError e(Field::rate, "give {rate} HZ");
  EXPECT_STREQ(e.what(), "give rate HZ");
  EXPECT_EQ(e.text(), "give {rate} HZ");
  EXPECT_EQ(e.field(), Field::rate);
  EXPECT_EQ(cubecal::cli::cli_message(e), "--rate: give --rate HZ");
  // A field whose messages say which option they are about gets no prefix.
  EXPECT_EQ(cubecal::cli::cli_message(cubecal::UsageError(Field::frame, "{frame}: sync=HEX is missing")),
            "--frame: sync=HEX is missing");
  const cubecal::InputError in("f.csv", 3, 0, "no rate", "give {rate} HZ");
  EXPECT_STREQ(in.what(), "f.csv:3: no rate (give rate HZ)");
  EXPECT_EQ(cubecal::cli::cli_message(in), "f.csv:3: no rate (give --rate HZ)");
  const cubecal::CalibrationError c(cubecal::CalibrationReason::degenerate, "the points are coplanar");
  EXPECT_EQ(cubecal::cli::cli_message(c), "the points are coplanar");
}

}  // namespace
