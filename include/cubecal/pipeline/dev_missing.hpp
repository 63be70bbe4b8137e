/// @file
/// `cubecal dev --gaps skip` as a library call: OADEV of every channel of a
/// record read with io::GapPolicy::skip (missing samples as NaN, gaps of
/// whole periods filled with them), each term that needs a missing sample left
/// out (stats/gap_deviation.hpp). Channels in parallel.
#pragma once
#include <cstddef>
#include <vector>

#include "cubecal/io/series.hpp"
#include "cubecal/pipeline/dev_pipeline.hpp"

namespace cubecal::pipeline {

/// The DevResult of run_dev, one segment (missing samples do not split the
/// record). A factor at which a channel has no whole term has no point (as
/// run_dev leaves out a factor no segment holds). UsageError(Field::stat) for a
/// statistic other than OADEV, UsageError when no averaging factor of the
/// grid fits the record, or when a channel has no whole term at any of them.
DevResult run_dev_skipping_missing(const io::Series& series, const DevRequest& request);

/// The missing samples of each channel of `series`, in channel order.
std::vector<std::size_t> missing_per_channel(const io::Series& series);

}  // namespace cubecal::pipeline
