#pragma once

// mobotd's SQLite store read from outside while the server runs, to check that a request that was
// refused changed nothing in it.

#include <chrono>
#include <filesystem>
#include <map>
#include <string>

namespace mobot::testing {

// Every table as text, row by row (each value's type, length and bytes), but for what the robot's
// own motion writes while it stands or drives: its trajectory and the distance of the run.
using DatabaseSnapshot = std::map<std::string, std::string>;

// One read transaction: the tables as of one moment. A table that cannot be read holds the error.
DatabaseSnapshot read_database(const std::filesystem::path& file);

// The names of the tables that differ, comma-separated; empty when none does.
std::string changed_tables(const DatabaseSnapshot& before, const DatabaseSnapshot& after);

// For a failure message: per table that differs, the first row that is not as it was (its
// printable characters).
std::string describe_changes(const DatabaseSnapshot& before, const DatabaseSnapshot& after);

// Reads the store until it reads the same twice, `spacing` apart: what an accepted command set
// going (a drive's stop, a goal reached, a sweep's end) has been written. Fails the test when it
// still changes after `timeout`.
DatabaseSnapshot settled_database(
    const std::filesystem::path& file,
    std::chrono::milliseconds spacing = std::chrono::milliseconds(200),
    std::chrono::milliseconds timeout = std::chrono::seconds(60));

}  // namespace mobot::testing
