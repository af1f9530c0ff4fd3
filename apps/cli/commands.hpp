#pragma once
/// @file commands.hpp
/// Sub-commands of `tetfsi`: run, validate, mesh, schema, report.
#include <string>

namespace tetfsi::cli {

/// Parses the command line and runs the chosen sub-command; returns the exit code.
/// Errors are thrown (see main.cpp for how they map to exit codes).
int dispatch(int argc, char** argv, const std::string& command_line);

}  // namespace tetfsi::cli
