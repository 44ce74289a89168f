#pragma once
// Files appear whole or not at all: written to a temporary name beside the target, flushed to
// disk, then renamed over it. A killed process leaves at most a stray *.tmp-<pid> file.

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>

namespace wheelpose {

void write_file_atomic(const std::filesystem::path& path, std::string_view contents);
void write_file_atomic(const std::filesystem::path& path, std::span<const std::uint8_t> contents);

// Reads a whole file; throws Error naming the path if it cannot.
std::string read_file(const std::filesystem::path& path);

// Creates a directory (and parents); throws Error naming it on failure.
void ensure_directory(const std::filesystem::path& path);

}  // namespace wheelpose
