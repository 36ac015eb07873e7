#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace mimpact::cli {

// Writes every file of `contents` (name -> text) into `directory` so that the directory is
// either complete or absent: a new directory is filled under a temporary name beside it and
// renamed into place; in an existing directory each file is written to a temporary name and
// renamed over the old one, and the files of `written_by_command` that this run does not
// write are removed (no stale forces.csv beside a new summary.json). Throws mimpact::Error
// naming the path on failure, after removing what it wrote.
void write_output_directory(const std::filesystem::path& directory,
                            const std::map<std::string, std::string>& contents,
                            const std::vector<std::string>& written_by_command);

}  // namespace mimpact::cli
