#include "output_directory.hpp"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <array>
#include <boost/program_options/errors.hpp>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <random>
#include <system_error>
#include <utility>
#include <vector>

#include "mimpact/common/error.hpp"

namespace mimpact::cli {

namespace fs = std::filesystem;

namespace {

// ".NAME.mimpact-staging-PID-N": where a run writes NAME before renaming it into place
constexpr const char* kStagingTag = ".mimpact-staging-";

std::string staging_prefix(const fs::path& directory) {
  std::string prefix(".");
  prefix += directory.filename().string();
  prefix += kStagingTag;
  return prefix;
}

fs::path staging_path(const fs::path& directory) {
  std::random_device device;
  return directory.parent_path() /
         (staging_prefix(directory) + std::to_string(::getpid()) + "-" + std::to_string(device()));
}

// Removes the staging directories of `directory` whose process is gone (killed while writing).
void remove_stale_staging(const fs::path& directory) {
  const std::string prefix = staging_prefix(directory);
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(
           directory.parent_path(), fs::directory_options::skip_permission_denied, error)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) != 0) continue;
    const long pid = std::strtol(name.c_str() + prefix.size(), nullptr, 10);
    if (pid > 0 && ::kill(pid_t(pid), 0) == -1 && errno == ESRCH) fs::remove_all(entry, error);
  }
}

// Holds SIGINT, SIGTERM and SIGHUP while it lives: they take effect once the directory is whole
// or absent.
class HeldSignals {
 public:
  HeldSignals() {
    sigset_t held;
    sigemptyset(&held);
    for (int signal : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&held, signal);
    pthread_sigmask(SIG_BLOCK, &held, &before_);
    // a file size limit (ulimit -f) is a failed write, not a killed process
    ::signal(SIGXFSZ, SIG_IGN);
  }
  ~HeldSignals() { pthread_sigmask(SIG_SETMASK, &before_, nullptr); }
  HeldSignals(const HeldSignals&) = delete;
  HeldSignals& operator=(const HeldSignals&) = delete;

 private:
  sigset_t before_;
};

[[noreturn]] void fail(const fs::path& path, const std::string& what) {
  throw Error(path.string() + ": " + what + ": " + std::strerror(errno) + "; nothing was written");
}

// A file of the staging directory: written unlinked (O_TMPFILE), so that a process killed before
// it is linked leaves nothing; named at once where the file system has no unlinked files.
struct StagedFile {
  int descriptor = -1;
  bool unlinked = false;
  fs::path path;
};

StagedFile open_staged(const fs::path& staging, const std::string& name) {
  StagedFile file{.path = staging / name};
  file.descriptor = ::open(staging.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0644);
  file.unlinked = file.descriptor >= 0;
  if (!file.unlinked)
    file.descriptor = ::open(file.path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (file.descriptor < 0) fail(file.path, "cannot create the file");
  return file;
}

void write_text(const StagedFile& file, const std::string& text) {
  for (std::size_t done = 0; done < text.size();) {
    const ssize_t written = ::write(file.descriptor, text.data() + done, text.size() - done);
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0) fail(file.path, "cannot write the file");
    done += std::size_t(written);
  }
}

void link_staged(const StagedFile& file) {
  if (!file.unlinked) return;
  const std::string self = "/proc/self/fd/" + std::to_string(file.descriptor);
  if (::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, file.path.c_str(), AT_SYMLINK_FOLLOW) != 0)
    fail(file.path, "cannot link the file");
}

// Puts `staging` in place of `directory`; an existing one is exchanged with it, then removed.
void commit(const fs::path& staging, const fs::path& directory) {
  std::error_code error;
  if (!fs::exists(directory, error)) {
    if (::rename(staging.c_str(), directory.c_str()) != 0) fail(directory, "cannot rename into");
    return;
  }
  if (::renameat2(AT_FDCWD, staging.c_str(), AT_FDCWD, directory.c_str(), RENAME_EXCHANGE) != 0) {
    // no exchange on this file system: the old directory aside, the new one in, in two steps
    const fs::path old = staging.string() + "-old";
    if (::rename(directory.c_str(), old.c_str()) != 0) fail(directory, "cannot replace");
    if (::rename(staging.c_str(), directory.c_str()) != 0) {
      const int cause = errno;
      ::rename(old.c_str(), directory.c_str());
      errno = cause;
      fail(directory, "cannot rename into");
    }
    fs::remove_all(old, error);
    return;
  }
  fs::remove_all(staging, error);  // the old directory, now under the staging name
}

}  // namespace

bool written_by_mimpact(const std::string& name) {
  static const std::array<const char*, 9> kNames = {
      "summary.json",         "forces.csv",   "velocities.csv",
      "bodies.csv",           "contacts.csv", "frame_forces.csv",
      "frame_velocities.csv", "paraview",     "force_chains.png"};
  for (const char* known : kNames)
    if (name == known) return true;
  return false;
}

fs::path check_output_directory(const std::string& out) {
  if (out.empty()) throw boost::program_options::error("--out is empty; allowed: a directory path");
  std::error_code error;
  const fs::path directory = fs::absolute(fs::path(out), error).lexically_normal();
  fs::path named = directory;
  if (!named.has_filename()) named = named.parent_path();  // "out/" names "out"
  const std::string shown = "--out " + out;
  if (named == named.root_path() || !named.has_filename())
    throw InvalidInput(shown + " is the root directory; allowed: a directory of its own");
  const fs::path working = fs::current_path(error);
  if (!error && std::mismatch(named.begin(), named.end(), working.begin(), working.end()).first ==
                    named.end())
    throw InvalidInput(shown +
                       " is the working directory or holds it; allowed: a directory of "
                       "its own");
  const fs::file_status status = fs::status(named, error);
  if (fs::exists(status) && !fs::is_directory(status))
    throw InvalidInput(shown +
                       " exists and is not a directory; allowed: a new path, or the "
                       "directory of an earlier run");
  if (fs::is_directory(status)) {
    for (const fs::directory_entry& entry : fs::directory_iterator(named, error)) {
      const std::string name = entry.path().filename().string();
      if (!written_by_mimpact(name))
        throw InvalidInput(shown + " holds \"" + name +
                           "\", which mimpact did not write; allowed: a new path, or the "
                           "directory of an earlier run (it is replaced as a whole)");
    }
  }
  remove_stale_staging(named);
  return named;
}

void write_output_directory(const fs::path& directory,
                            const std::map<std::string, std::string>& contents) {
  const HeldSignals held;
  std::error_code error;
  fs::create_directories(directory.parent_path(), error);
  const fs::path staging = staging_path(directory);
  if (!fs::create_directory(staging, error)) {
    errno = error.value();
    fail(staging, "cannot create the directory");
  }
  std::vector<StagedFile> files;
  try {
    for (const auto& [name, text] : contents) {
      files.push_back(open_staged(staging, name));
      write_text(files.back(), text);
    }
    for (const StagedFile& file : files) link_staged(file);
    for (StagedFile& file : files) ::close(std::exchange(file.descriptor, -1));
    commit(staging, directory);
  } catch (...) {
    for (const StagedFile& file : files)
      if (file.descriptor >= 0) ::close(file.descriptor);
    fs::remove_all(staging, error);
    throw;
  }
}

}  // namespace mimpact::cli
