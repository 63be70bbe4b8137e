/// @file
/// The report page of `cubecal plan --report DIR`: the plan's table and, per
/// channel, a log-log plot of each term's precision against record length
/// (plan_<channel>), the targets as horizontal lines in the term's colour and
/// the planned lengths (and the precision at the asked length) marked on the
/// curves. Write it with write_command_report (command_report.hpp).
#pragma once
#include <string>
#include <vector>

#include "cubecal/pipeline/plan.hpp"
#include "cubecal/report/command_report.hpp"

namespace cubecal::report {

/// One figure per channel (above). Throws nothing beyond std::bad_alloc.
std::vector<ReportFigure> plan_figures(const pipeline::PlanResult& r);

/// The plan page; `command` is the command line as typed. Throws nothing beyond std::bad_alloc.
CommandReport plan_report(const pipeline::PlanResult& r, const std::string& command);

}  // namespace cubecal::report
