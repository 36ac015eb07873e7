#include "output_directory.hpp"

#include <fstream>
#include <random>
#include <system_error>

#include "mimpact/common/error.hpp"

namespace mimpact::cli {

namespace fs = std::filesystem;

namespace {

std::string unique_suffix() {
  std::random_device device;
  return ".partial-" + std::to_string(device());
}

void write_file(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  out.close();
  if (!out) throw Error(path.string() + ": cannot write the file");
}

}  // namespace

void write_output_directory(const fs::path& requested,
                            const std::map<std::string, std::string>& contents,
                            const std::vector<std::string>& written_by_command) {
  // "out/" and "out/." name the directory "out"; renaming into place needs its own name
  fs::path directory = requested.lexically_normal();
  while (!directory.empty() && (!directory.has_filename() || directory.filename() == "."))
    directory = directory.parent_path();
  if (directory.empty()) directory = fs::current_path();
  std::error_code error;
  if (fs::exists(directory, error)) {
    if (!fs::is_directory(directory, error))
      throw Error(directory.string() +
                  ": exists and is not a directory; allowed: a directory "
                  "or a path that does not exist yet");
    for (const auto& [name, text] : contents) {
      const fs::path partial = directory / (name + unique_suffix());
      try {
        write_file(partial, text);
      } catch (...) {
        fs::remove(partial, error);
        throw;
      }
      fs::rename(partial, directory / name, error);
      if (error) throw Error((directory / name).string() + ": " + error.message());
    }
    for (const std::string& name : written_by_command)
      if (!contents.count(name) && (fs::remove(directory / name, error), error))
        throw Error((directory / name).string() +
                    ": cannot remove this file of an earlier run: " + error.message());
    return;
  }
  const fs::path parent = directory.has_parent_path() ? directory.parent_path() : fs::path(".");
  const fs::path partial = parent / (directory.filename().string() + unique_suffix());
  try {
    fs::create_directories(partial);
    for (const auto& [name, text] : contents) write_file(partial / name, text);
    fs::rename(partial, directory);
  } catch (const fs::filesystem_error& failure) {
    fs::remove_all(partial, error);
    throw Error(directory.string() + ": " + failure.what());
  } catch (...) {
    fs::remove_all(partial, error);
    throw;
  }
}

}  // namespace mimpact::cli
