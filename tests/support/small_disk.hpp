// A small tmpfs for the full-disk tests: mounted for the life of the object when the
// tests run as root (CI does), else not mounted and the test skips with a message.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <string>

#include <unistd.h>

namespace slide::testing {

class SmallDisk {
 public:
  SmallDisk(const std::filesystem::path& folder, int kibibytes) : folder_(folder) {
    std::filesystem::create_directories(folder_);
    const std::string command = "mount -t tmpfs -o size=" + std::to_string(kibibytes) +
                                "k slide-test-tmpfs '" + folder_.string() + "' 2>/dev/null";
    mounted_ = ::geteuid() == 0 && std::system(command.c_str()) == 0;
  }
  ~SmallDisk() {
    if (mounted_) std::system(("umount '" + folder_.string() + "'").c_str());
  }
  SmallDisk(const SmallDisk&) = delete;
  SmallDisk& operator=(const SmallDisk&) = delete;
  bool mounted() const { return mounted_; }

 private:
  std::filesystem::path folder_;
  bool mounted_ = false;
};

}  // namespace slide::testing
