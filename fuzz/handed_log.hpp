// What a record source's framer (line_framer, frame_decoder) handed on, as
// the fuzz targets keep it: the bytes accounted for, and a log of samples and
// rejects for comparing one way of feeding the input with another.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace cubecal::fuzz {

struct HandedLog {
  std::size_t handed = 0;  // input bytes handed on as samples or rejects
  std::string text;

  void layout(std::size_t columns) { text += "L" + std::to_string(columns) + "\n"; }
  void sample(std::string_view fields, std::size_t bytes) {
    handed += bytes;
    (text += "S").append(fields) += "\n";
  }
  void reject(std::string_view reason, std::string_view data) {
    handed += data.size();
    ((text += "R").append(reason) += '|').append(data) += "\n";
  }
};

}  // namespace cubecal::fuzz
