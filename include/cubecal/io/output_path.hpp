/// @file
/// Where results go, checked before any work: a file output must not be a
/// directory, must live in a directory that exists and can be written, and is
/// replaced only when asked; a directory output is created (with its parents)
/// and must be writable. Every failure is a one-line UsageError saying what to
/// do, so that no run fails after the work for want of a place to write.
#pragma once
#include <string>
#include <vector>

#include "cubecal/field.hpp"

namespace cubecal::io {

/// A file to be written at `path` (the writer creates PATH.partial and renames
/// it into place). `option` is the request field the path came from ("out").
void check_output_file(const std::string& path, bool force, Field option = Field::out);

/// A directory to write results into: created when missing; `files` are the
/// names the run will write in it, refused when one exists and !force.
void prepare_output_dir(const std::string& dir, bool force, const std::vector<std::string>& files,
                        Field option = Field::out);

}  // namespace cubecal::io
