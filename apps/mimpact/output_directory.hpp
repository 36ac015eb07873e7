#pragma once

#include <filesystem>
#include <map>
#include <string>

// The --out directory of a command: complete or absent, whatever happens while it is written.
namespace mimpact::cli {

// The names a command's output directory may hold: what `mimpact chain` and `mimpact packing`
// write, and what `python3 -m mimpact.packing_output` adds (paraview/, force_chains.png). An
// existing directory holding anything else is not the output of a run, and is never replaced.
bool written_by_mimpact(const std::string& name);

// Checks --out before any work: given, not empty, not the root, not a file, and, when it exists,
// a directory holding only what mimpact writes. Removes what runs killed while writing left
// beside it (their staging directories, named after their process). Throws InvalidInput (and
// boost's po::error for an empty value).
std::filesystem::path check_output_directory(const std::string& out);

// Writes `contents` (name -> text) as the directory `directory` (checked by
// check_output_directory) in one step: the files are written unlinked (O_TMPFILE) into a
// staging directory beside it, linked there once all are written, and the staging directory is
// renamed into place (exchanged with an existing one, which is then removed). SIGINT, SIGTERM
// and SIGHUP wait until the directory is whole or absent; a SIGKILL leaves at most the empty
// staging directory, which the next run removes; a write error (a full disk) removes what was
// written and keeps an existing directory as it was. Throws mimpact::Error naming the path.
void write_output_directory(const std::filesystem::path& directory,
                            const std::map<std::string, std::string>& contents);

}  // namespace mimpact::cli
