#include "detail/container_streams.hpp"
namespace cubecal::io::detail {
std::unique_ptr<SampleStream> open_hdf5_stream(const std::string&, const SeriesOptions&) { return nullptr; }
}  // namespace cubecal::io::detail
