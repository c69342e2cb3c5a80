#pragma once
// The geovoronoi tool's output folder, renamed into place only when complete.
#include "usage_error.hpp"

#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>

#include <unistd.h>

namespace gvcli {

namespace fs = std::filesystem;

/// The output folder: everything is written to DIR.partial-<pid> and moved into DIR by commit();
/// if the command fails, the partial folder is removed, so no half-written output looks complete.
class output_dir {
 public:
  explicit output_dir(const std::string& dir) : final_(dir) {
    if (dir.empty()) throw usage_error("--out needs a folder name");
    if (fs::exists(final_) && !fs::is_directory(final_)) throw usage_error(dir + ": exists and is not a folder");
    fs::path parent = final_.parent_path();
    if (!parent.empty() && !fs::is_directory(parent))
      throw usage_error(dir + ": the parent folder " + parent.string() + " does not exist");
    temp_ = final_;
    temp_ += ".partial-" + std::to_string(::getpid());
    std::error_code ec;
    fs::remove_all(temp_, ec);
    if (!fs::create_directory(temp_, ec) || ec) throw usage_error(dir + ": cannot create the output folder " + temp_.string());
  }
  ~output_dir() {
    if (!committed_) {
      std::error_code ec;
      fs::remove_all(temp_, ec);
    }
  }
  output_dir(const output_dir&) = delete;
  output_dir& operator=(const output_dir&) = delete;

  /// Path of a file (or subfolder, created) inside the temporary folder.
  std::string file(const std::string& name) const { return (temp_ / name).string(); }
  std::string subdir(const std::string& name) const {
    fs::create_directories(temp_ / name);
    return (temp_ / name).string();
  }

  /// Moves the finished outputs into place: the whole folder when DIR does not exist (or is empty),
  /// else file by file (each rename replaces the old file at once).
  void commit() {
    std::error_code ec;
    if (fs::exists(final_) && fs::is_empty(final_)) fs::remove(final_, ec);
    if (!fs::exists(final_)) {
      fs::rename(temp_, final_, ec);
      if (ec) throw std::runtime_error(final_.string() + ": cannot move the outputs into place: " + ec.message());
    } else {
      move_into(temp_, final_);
      fs::remove_all(temp_, ec);
    }
    committed_ = true;
  }

 private:
  static void move_into(const fs::path& from, const fs::path& to) {
    for (const auto& e : fs::directory_iterator(from)) {
      const fs::path target = to / e.path().filename();
      if (e.is_directory()) {
        if (fs::exists(target) && !fs::is_directory(target)) fs::remove(target);
        fs::create_directories(target);
        move_into(e.path(), target);
      } else {
        fs::rename(e.path(), target);
      }
    }
  }
  fs::path final_, temp_;
  bool committed_ = false;
};

}  // namespace gvcli
