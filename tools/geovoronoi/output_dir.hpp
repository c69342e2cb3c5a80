#pragma once
// The output folder of one geovoronoi run, committed as a whole (docs/cli.md, "Output folder").
//
// Everything is written into a fresh sibling folder DIR.partial-<pid>; commit() then swaps that
// folder with DIR in one step (renameat2 RENAME_EXCHANGE where the system has it, else DIR is moved
// aside to DIR.old-<pid> and the partial folder renamed to DIR, with the old one moved back if that
// fails) and removes the previous contents. So DIR is at every moment either the previous complete
// output or the new complete output, never a mix, and no file of an earlier run survives.
//
// Concurrent runs on one DIR: the commit holds an exclusive flock() on the parent folder and checks
// that DIR is still the folder it found when the run started (same device and inode, or still
// absent). A run that finds DIR replaced by another run in the meantime discards its own outputs and
// fails with one line (exit 1), so one run wins whole.
//
// Checks before anything is computed (usage errors, exit 2): DIR is not a file or a dangling link,
// its names fit the file system, its parent exists and a folder can be created in it, DIR does not
// contain a file the run read (any file recorded by the run's io::read_log: checked again at the
// commit, for files read meanwhile), and an
// existing non-empty DIR carries the marker file of a geovoronoi output (so `--out ~` can never wipe a
// folder of the user's own files).
//
// Signals: SIGINT, SIGTERM and SIGHUP remove the partial folder (with async-signal-safe calls only)
// and then end the process as the signal would; during the swap itself they are blocked in the
// committing thread and only noted in any other, and acted on once the swap is done. A run killed
// without a chance to clean up (SIGKILL, power loss) leaves DIR.partial-<pid>; the next run on the
// same DIR removes partial folders whose process is gone.

#include "usage_error.hpp"

#include <geovoronoi/error.hpp>
#include <geovoronoi/io/common.hpp>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <fcntl.h>
#include <sched.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>
#if defined(__linux__)
#include <sys/syscall.h>
#endif

namespace gvcli {

namespace fs = std::filesystem;

/// A failure that is not the user's fault (I/O, disk full, a concurrent run): exit code 1.
struct runtime_failure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Name of the marker file every output folder carries.
inline const char* output_marker() { return ".geovoronoi-output"; }

namespace detail {

/// The partial folder of the live output_dir (one per process), for the signal handler and for
/// telling output failures (exit 1) from input failures (exit 2).
struct partial_state {
  int parent_fd = -1;       // the parent folder, opened once
  char name[1024] = {0};    // the partial folder's name inside it
  std::string path;         // its full path, and the final folder's, for messages
  std::string final_path;
  // During the swap a signal (which another thread may take, as only the committing thread blocks
  // them) is only noted; the commit acts on it when the swap is done.
  // (lock-free atomics, safe in a signal handler; Dekker-style: the handler announces itself in
  // `entering` before it looks at `committing`, the commit sets `committing` before it looks at
  // `entering`, so the swap never runs while a handler removes the folder.)
  std::atomic<int> committing{0};
  std::atomic<int> entering{0};
  std::atomic<int> pending{0};
  struct sigaction old[3];
};
inline partial_state& partial() {
  static partial_state s;
  return s;
}
inline const int handled_signals[3] = {SIGINT, SIGTERM, SIGHUP};

/// Removes `name` inside the folder `parent` and everything under it, using only system calls that
/// may run inside a signal handler. Best effort; depth-limited.
inline void remove_tree_at(int parent, const char* name, int depth) noexcept {
  if (::unlinkat(parent, name, 0) == 0 || errno == ENOENT) return;
#if defined(__linux__)
  if (depth > 16) return;
  const int fd = ::openat(parent, name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return;
  alignas(8) char buf[4096];
  for (int pass = 0; pass < 64; ++pass) {  // entries removed while reading may be skipped: reread
    bool any = false;
    ::lseek(fd, 0, SEEK_SET);
    for (;;) {
      const long n = ::syscall(SYS_getdents64, fd, buf, sizeof buf);
      if (n <= 0) break;
      for (long off = 0; off < n;) {
        unsigned short reclen;
        std::memcpy(&reclen, buf + off + 16, sizeof reclen);  // struct linux_dirent64: d_reclen at 16
        const char* entry = buf + off + 19;                   // d_name at 19
        off += reclen;
        if (entry[0] == '.' && (entry[1] == '\0' || (entry[1] == '.' && entry[2] == '\0'))) continue;
        remove_tree_at(fd, entry, depth + 1);
        any = true;
      }
    }
    if (!any) break;
  }
  ::close(fd);
#else
  (void)depth;
#endif
  ::unlinkat(parent, name, AT_REMOVEDIR);
}

/// Removes the partial folder; retried, as another thread may still be writing into it.
inline void remove_partial_now() noexcept {
  partial_state& s = partial();
  struct stat st;
  for (int k = 0; k < 8 && s.parent_fd >= 0 && s.name[0]; ++k) {
    remove_tree_at(s.parent_fd, s.name, 0);
    if (::fstatat(s.parent_fd, s.name, &st, AT_SYMLINK_NOFOLLOW) != 0) break;
  }
}

inline void on_signal(int sig) noexcept {
  const int saved = errno;
  partial_state& s = partial();
  s.entering.store(1);
  if (s.committing.load()) {
    s.pending.store(sig);
    s.entering.store(0);
    errno = saved;
    return;
  }
  remove_partial_now();  // entering stays 1: the process ends below
  errno = saved;
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

/// Marks the swap; when it ends (done or failed), a signal noted meanwhile removes what is left
/// under the partial name (the previous outputs, or this run's discarded ones) and ends the process.
class committing_guard {
 public:
  committing_guard() {
    partial_state& s = partial();
    s.committing.store(1);
    while (s.entering.load()) ::sched_yield();  // a handler removing the folder ends the process
  }
  ~committing_guard() {
    partial_state& s = partial();
    s.committing.store(0);
    if (const int sig = s.pending.load()) {
      remove_partial_now();
      ::signal(sig, SIG_DFL);
      ::raise(sig);
    }
  }
  committing_guard(const committing_guard&) = delete;
  committing_guard& operator=(const committing_guard&) = delete;
};

/// Whether process @p pid is gone (so its partial folder is abandoned).
inline bool process_gone(long pid) { return pid > 0 && ::kill(pid_t(pid), 0) != 0 && errno == ESRCH; }

/// Swaps the folders a and b (both exist) in one step where the system can; false if it cannot.
inline bool exchange(int dirfd, const char* a, const char* b) {
#if defined(__linux__) && defined(SYS_renameat2)
  return ::syscall(SYS_renameat2, dirfd, a, dirfd, b, 2u /* RENAME_EXCHANGE */) == 0;
#else
  (void)dirfd, (void)a, (void)b;
  errno = ENOSYS;
  return false;
#endif
}

/// Identity of a path: device and inode, or absent.
struct identity {
  bool exists = false;
  dev_t dev = 0;
  ino_t ino = 0;
  bool operator==(const identity& o) const { return exists == o.exists && dev == o.dev && ino == o.ino; }
};
inline identity identity_of(int dirfd, const char* name) {
  identity id;
  struct stat st;
  if (::fstatat(dirfd, name, &st, AT_SYMLINK_NOFOLLOW) == 0) id.exists = true, id.dev = st.st_dev, id.ino = st.st_ino;
  return id;
}

/// Blocks the handled signals for its lifetime.
class signals_blocked {
 public:
  signals_blocked() {
    sigset_t set;
    sigemptyset(&set);
    for (int s : handled_signals) sigaddset(&set, s);
    pthread_sigmask(SIG_BLOCK, &set, &old_);
  }
  ~signals_blocked() { pthread_sigmask(SIG_SETMASK, &old_, nullptr); }
  signals_blocked(const signals_blocked&) = delete;
  signals_blocked& operator=(const signals_blocked&) = delete;

 private:
  sigset_t old_;
};

/// Holds an exclusive flock() on a folder for its lifetime.
class folder_lock {
 public:
  explicit folder_lock(int dirfd) : fd_(dirfd) {
    while (::flock(fd_, LOCK_EX) != 0 && errno == EINTR) {
    }
  }
  ~folder_lock() { ::flock(fd_, LOCK_UN); }
  folder_lock(const folder_lock&) = delete;
  folder_lock& operator=(const folder_lock&) = delete;

 private:
  int fd_;
};

}  // namespace detail

/// Whether @p message names a file inside the live partial output folder (an output failure). The
/// path is then rewritten to the final folder's, which is what the user named.
inline bool is_output_failure(std::string& message) {
  const auto& s = detail::partial();
  if (s.path.empty()) return false;
  const auto at = message.find(s.path + "/");
  if (at == std::string::npos) return false;
  message.replace(at, s.path.size(), s.final_path);
  return true;
}

/// The output folder of one run, see the top of this file.
class output_dir {
 public:
  /// Checks @p dir (the --out value) against the rules above and creates the partial folder. No file
  /// that @p reads recorded (every file the run read: inputs, a header's data file, points, meshes)
  /// may lie inside it; checked here and again at commit(), for files read in between.
  output_dir(const std::string& dir, const geovoronoi::io::read_log& reads, std::string command = "geovoronoi")
      : shown_(dir), command_(std::move(command)), reads_(&reads) {
    if (dir.empty()) throw usage_error("--out needs a folder name");
    std::string d = dir;
    while (d.size() > 1 && d.back() == '/') d.pop_back();  // `--out newdir/` names newdir
    fs::path p(d);
    if (p.filename() == "." || p.filename() == ".." || p == p.root_path())
      throw usage_error(dir + ": --out must name a folder to create or replace, not '.', '..' or '/'");
    // a name longer than a file system allows (255 bytes; the folder's own name also carries the
    // .partial-<pid> suffix while the run writes aside) fails every later step with a vaguer message
    for (const auto& part : p) {
      const std::string n = part.string();
      const std::size_t limit = part == p.filename() ? max_name - partial_suffix_room : max_name;
      if (n.size() > limit)
        throw usage_error(dir + ": the name '" + geovoronoi::printable(n) + "' is " + std::to_string(n.size()) +
                          " bytes long; a file system allows " + std::to_string(max_name) + " bytes per name" +
                          (part == p.filename() ? " (less " + std::to_string(partial_suffix_room) +
                                                      " for the .partial-<pid> suffix of the folder written aside)"
                                                : std::string()));
    }
    std::error_code ec;
    const auto ls = fs::symlink_status(p, ec);
    if (fs::is_symlink(ls)) {
      const auto target = fs::status(p, ec);
      if (!fs::exists(target)) throw usage_error(dir + ": is a symbolic link to a missing target (dangling link)");
      if (!fs::is_directory(target)) throw usage_error(dir + ": exists and is not a folder");
      p = fs::canonical(p, ec);  // replace the folder the link points to; the link stays
      if (ec) throw usage_error(dir + ": cannot resolve the symbolic link: " + ec.message());
    } else if (fs::exists(ls) && !fs::is_directory(ls)) {
      throw usage_error(dir + ": exists and is not a folder");
    }
    final_ = fs::absolute(p, ec).lexically_normal();
    const fs::path parent = final_.parent_path();
    check_parent(dir, p, parent);
    check_reads();
    if (fs::is_directory(final_, ec) && !fs::is_empty(final_, ec) && !fs::exists(final_ / output_marker(), ec))
      throw usage_error(dir + ": exists and holds files that geovoronoi did not write (no " + output_marker() +
                        " marker); --out replaces the whole folder, so name a new or empty folder");
    parent_fd_ = ::open(parent.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (parent_fd_ < 0) throw usage_error(dir + ": cannot open the parent folder: " + std::strerror(errno));
    name_ = final_.filename().string();
    partial_name_ = name_ + ".partial-" + std::to_string(::getpid());
    {
      detail::folder_lock lock(parent_fd_);
      clean_abandoned();
      start_ = detail::identity_of(parent_fd_, name_.c_str());
    }
    detail::remove_tree_at(parent_fd_, partial_name_.c_str(), 0);  // a dead process with our pid
    if (::mkdirat(parent_fd_, partial_name_.c_str(), 0777) != 0) {
      const int e = errno;
      ::close(parent_fd_);
      const std::string why = dir + ": cannot create a folder in " + parent.string() + ": " + std::strerror(e);
      if (e == ENOSPC || e == EDQUOT || e == EIO) throw runtime_failure(why);  // not the user's input: exit 1
      throw usage_error(why);
    }
    temp_ = parent / partial_name_;
    install_handlers();
  }
  ~output_dir() {
    if (!committed_) detail::remove_tree_at(parent_fd_, partial_name_.c_str(), 0);
    remove_handlers();
    ::close(parent_fd_);
  }
  output_dir(const output_dir&) = delete;
  output_dir& operator=(const output_dir&) = delete;

  /// Path of a file (or subfolder, created) inside the partial folder.
  std::string file(const std::string& name) const { return (temp_ / name).string(); }
  std::string subdir(const std::string& name) const {
    if (name.empty() || name == ".") return temp_.string();
    fs::create_directories(temp_ / name);
    return (temp_ / name).string();
  }

  /// Puts the finished outputs in place as a whole, or throws runtime_failure and leaves DIR as it was.
  void commit() {
    check_reads();  // a file read since the start must not be swapped away either
    {
      const std::string marker = file(output_marker());
      std::ofstream m(marker);
      m << "This folder was written by " << command_
        << ". geovoronoi replaces it as a whole on the next run with the same --out.\n";
      m.close();
      if (!m) throw runtime_failure(shown_ + "/" + output_marker() + ": write error (disk full?)");
    }
    detail::committing_guard guard;  // destroyed last: acts on a signal once the lock is released
    detail::signals_blocked blocked;
    detail::folder_lock lock(parent_fd_);
    const char* fin = name_.c_str();
    const char* tmp = partial_name_.c_str();
    if (!(detail::identity_of(parent_fd_, fin) == start_))
      throw runtime_failure(shown_ + ": another run replaced this folder while this one was computing; kept its "
                            "outputs and discarded this run's");
    if (!start_.exists) {
      if (::renameat(parent_fd_, tmp, parent_fd_, fin) != 0) fail("cannot move the outputs into place");
    } else if (!detail::exchange(parent_fd_, tmp, fin)) {
      // no atomic exchange here: move the old folder aside, the new one in, the old one back on failure
      const std::string old = name_ + ".old-" + std::to_string(::getpid());
      detail::remove_tree_at(parent_fd_, old.c_str(), 0);
      if (::renameat(parent_fd_, fin, parent_fd_, old.c_str()) != 0) fail("cannot move the previous outputs aside");
      if (::renameat(parent_fd_, tmp, parent_fd_, fin) != 0) {
        const int e = errno;
        ::renameat(parent_fd_, old.c_str(), parent_fd_, fin);
        errno = e;
        fail("cannot move the outputs into place");
      }
      if (::renameat(parent_fd_, old.c_str(), parent_fd_, tmp) != 0) detail::remove_tree_at(parent_fd_, old.c_str(), 0);
    }
    committed_ = true;
    detail::remove_tree_at(parent_fd_, tmp, 0);  // the previous outputs, now under the partial name
  }

 private:
  static constexpr std::size_t max_name = 255;            // NAME_MAX of Linux's file systems
  static constexpr std::size_t partial_suffix_room = 20;  // ".partial-" and a pid of up to 11 digits

  /// The parent folder of the output must exist and be a folder: a one-line error naming what it is
  /// instead (missing, a file, a path the system cannot handle).
  void check_parent(const std::string& dir, const fs::path& given, const fs::path& parent) const {
    struct stat st;
    if (::stat(parent.c_str(), &st) == 0) {
      if (S_ISDIR(st.st_mode)) return;
      throw usage_error(dir + ": the parent " + parent.string() + " is a file, not a folder");
    }
    const int e = errno;
    if (e == ENAMETOOLONG)
      throw usage_error(dir + ": the folder's absolute path " + std::string(given.is_absolute() ? "" : "(from the working folder) ") +
                        "is " + std::to_string(final_.string().size()) +
                        " bytes long, more than the system handles (PATH_MAX, 4096 bytes on Linux); use a shorter path");
    if (e == ENOTDIR)
      throw usage_error(dir + ": the parent " + parent.string() + " does not exist (a part of its path is a file, not a folder)");
    if (e == ENOENT) throw usage_error(dir + ": the parent folder " + parent.string() + " does not exist");
    throw usage_error(dir + ": the parent folder " + parent.string() + " cannot be used: " + std::strerror(e));
  }

  /// No file the run read (reads_) lies inside the output folder, which the swap replaces as a whole.
  void check_reads() const {
    std::error_code ec;
    const fs::path fp = fs::weakly_canonical(final_, ec);
    if (ec) throw usage_error(shown_ + ": cannot resolve the folder's path: " + ec.message());
    for (const auto& in : reads_->paths()) {
      std::error_code ei;
      fs::path ip = fs::weakly_canonical(fs::absolute(in, ei), ei);
      if (ei) ip = fs::absolute(in).lexically_normal();
      auto f = fp.begin(), i = ip.begin();
      while (f != fp.end() && i != ip.end() && *f == *i) ++f, ++i;
      if (f == fp.end())
        throw usage_error(shown_ + ": the output folder contains the input " + in +
                          " (the folder is replaced as a whole); choose another --out");
    }
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw runtime_failure(shown_ + ": " + what + ": " + std::strerror(errno));
  }

  /// Removes NAME.partial-<pid> folders of processes that are gone; a NAME.old-<pid> of a dead
  /// process is the previous output of a run killed inside the fallback swap: put back if NAME is missing.
  void clean_abandoned() {
    std::error_code ec;
    const fs::path parent = final_.parent_path();
    for (fs::directory_iterator it(parent, ec), end; !ec && it != end; it.increment(ec)) {
      const std::string n = it->path().filename().string();
      for (const char* kind_c : {".partial-", ".old-"}) {
        const std::string kind = kind_c, prefix = name_ + kind;
        if (n.size() <= prefix.size() || n.compare(0, prefix.size(), prefix) != 0) continue;
        const std::string digits = n.substr(prefix.size());
        if (digits.find_first_not_of("0123456789") != std::string::npos || digits.size() > 9) continue;
        const long pid = std::strtol(digits.c_str(), nullptr, 10);
        if (!detail::process_gone(pid)) continue;
        if (kind == ".old-" && !detail::identity_of(parent_fd_, name_.c_str()).exists &&
            ::renameat(parent_fd_, n.c_str(), parent_fd_, name_.c_str()) == 0)
          continue;
        detail::remove_tree_at(parent_fd_, n.c_str(), 0);
      }
    }
  }

  void install_handlers() {
    auto& s = detail::partial();
    s.parent_fd = parent_fd_;
    std::memcpy(s.name, partial_name_.c_str(), partial_name_.size() + 1);
    s.path = temp_.string();
    s.final_path = shown_;
    while (!s.final_path.empty() && s.final_path.size() > 1 && s.final_path.back() == '/') s.final_path.pop_back();
    struct sigaction sa;
    std::memset(&sa, 0, sizeof sa);
    sa.sa_handler = detail::on_signal;
    sigemptyset(&sa.sa_mask);
    for (int i = 0; i < 3; ++i) {
      ::sigaction(detail::handled_signals[i], nullptr, &s.old[i]);
      if (s.old[i].sa_handler != SIG_IGN) ::sigaction(detail::handled_signals[i], &sa, nullptr);  // keep nohup
    }
  }
  void remove_handlers() {
    auto& s = detail::partial();
    for (int i = 0; i < 3; ++i) ::sigaction(detail::handled_signals[i], &s.old[i], nullptr);
    s.parent_fd = -1;
    s.name[0] = '\0';  // path and final_path stay: the exception that ended the run is reported later
  }

  std::string shown_, command_;
  const geovoronoi::io::read_log* reads_;
  fs::path final_, temp_;
  std::string name_, partial_name_;
  int parent_fd_ = -1;
  detail::identity start_;
  bool committed_ = false;
};

}  // namespace gvcli
