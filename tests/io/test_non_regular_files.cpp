// Non-regular inputs are never read without bound: devices (/dev/zero, /dev/urandom) are refused
// by type, pipes are read up to a limit, and the size of a regular transform file is checked
// before it is read. Clouds and transforms (--initial / --ground-truth) alike.
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <string>
#include <thread>

#include "io/file_access.hpp"
#include "io_test_util.hpp"
#include "ppcr/io.hpp"

namespace {

// Writes `text` into a FIFO once, or endlessly (until the reader closes) when `endless`.
// SIGPIPE is ignored while the test runs so that the reader closing ends the writer with EPIPE.
// The writer waits for a reader with non-blocking opens, so that it ends even if none comes.
class FifoWriter {
 public:
  FifoWriter(std::string path, std::string text, bool endless)
      : path_(std::move(path)), thread_([this, text, endless] { run(text, endless); }) {}
  ~FifoWriter() {
    stop_ = true;
    thread_.join();
  }

 private:
  void run(const std::string& text, bool endless) {
    int fd = -1;
    while (fd < 0 && !stop_) {
      fd = ::open(path_.c_str(), O_WRONLY | O_NONBLOCK);  // ENXIO until a reader opens it
      if (fd < 0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    if (fd < 0) return;
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    do {
      if (::write(fd, text.data(), text.size()) < 0) break;
    } while (endless);
    ::close(fd);
  }
  std::string path_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

struct IgnoreSigpipe {
  IgnoreSigpipe() { old = ::signal(SIGPIPE, SIG_IGN); }
  ~IgnoreSigpipe() { ::signal(SIGPIPE, old); }
  void (*old)(int);
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Makes a FIFO `name` in `dir` and runs read(path) while a FifoWriter feeds it `text` (once, or
// endlessly); returns read's Status.
template <typename Read>
ppcr::Status read_through_fifo(const io_test::TempDir& dir, const std::string& name,
                               const std::string& text, bool endless, Read read) {
  const std::string fifo = dir.file(name);
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  IgnoreSigpipe ignore;
  FifoWriter writer(fifo, text, endless);
  return read(fifo);
}

}  // namespace

TEST_CASE("Devices are refused by type, as clouds and as transforms", "[io][non_regular]") {
  for (const char* device : {"/dev/zero", "/dev/urandom"}) {
    if (!std::filesystem::exists(device)) continue;
    const auto t0 = std::chrono::steady_clock::now();
    ppcr::PointCloud cloud;
    ppcr::Status s = ppcr::io::read_cloud(device, &cloud);
    INFO(s.to_string());
    CHECK(s.code() == ppcr::StatusCode::kIoError);
    CHECK_THAT(s.message(), Catch::Contains(device) && Catch::Contains("character device"));
    Eigen::Isometry3d T;
    s = ppcr::io::read_transform(device, &T);
    INFO(s.to_string());
    CHECK(s.code() == ppcr::StatusCode::kIoError);
    CHECK_THAT(s.message(), Catch::Contains(device) && Catch::Contains("character device") &&
                                Catch::Contains("4x4 matrix"));
    CHECK(seconds_since(t0) < 1.0);
  }
}

TEST_CASE("A cloud through a FIFO still reads", "[io][non_regular]") {
  io_test::TempDir dir;
  ppcr::PointCloud cloud;
  const ppcr::Status s = read_through_fifo(
      dir, "cloud.xyz", "1 2 3\n4 5 6\n", false,
      [&](const std::string& path) { return ppcr::io::read_cloud(path, &cloud); });
  INFO(s.to_string());
  REQUIRE(s.ok());
  CHECK(cloud.size() == 2u);
}

TEST_CASE("A transform FIFO that never ends is refused at the size limit", "[io][non_regular]") {
  io_test::TempDir dir;
  Eigen::Isometry3d T;
  const auto t0 = std::chrono::steady_clock::now();
  const ppcr::Status s = read_through_fifo(
      dir, "T.txt", std::string(4096, '0') + " ", true,
      [&](const std::string& path) { return ppcr::io::read_transform(path, &T); });
  INFO(s.to_string());
  CHECK(s.code() == ppcr::StatusCode::kIoError);
  CHECK_THAT(s.message(), Catch::Contains(dir.file("T.txt")) && Catch::Contains("pipe (FIFO)") &&
                              Catch::Contains("more than 1048576 bytes"));
  CHECK(seconds_since(t0) < 10.0);
}

TEST_CASE("A cloud FIFO that never ends stops at the limit", "[io][non_regular]") {
  // The cloud limit for pipes is 1 GiB; the same bounded read is run here with a small limit.
  io_test::TempDir dir;
  std::string bytes;
  const ppcr::Status s =
      read_through_fifo(dir, "endless.xyz", "1 2 3\n", true, [&](const std::string& path) {
        return ppcr::io::detail::read_file_bytes(path, {1000, 100000, "a point cloud"}, &bytes);
      });
  INFO(s.to_string());
  CHECK(s.code() == ppcr::StatusCode::kIoError);
  CHECK_THAT(s.message(), Catch::Contains(dir.file("endless.xyz")) &&
                              Catch::Contains("more than 100000 bytes") &&
                              Catch::Contains("a point cloud"));
  CHECK(bytes.empty());
}

TEST_CASE("The size of a transform file is checked before it is read", "[io][non_regular]") {
  io_test::TempDir dir;
  const std::string path = dir.file("huge_T.txt");
  io_test::write_bytes(path, "1 0 0 0\n");
  std::filesystem::resize_file(path, std::uintmax_t{1} << 30);  // sparse: nothing is written
  const auto t0 = std::chrono::steady_clock::now();
  Eigen::Isometry3d T;
  const ppcr::Status s = ppcr::io::read_transform(path, &T);
  INFO(s.to_string());
  CHECK(s.code() == ppcr::StatusCode::kIoError);
  CHECK_THAT(s.message(), Catch::Contains(path) && Catch::Contains("1073741824 bytes") &&
                              Catch::Contains("limit 1048576"));
  CHECK(seconds_since(t0) < 0.5);
}
