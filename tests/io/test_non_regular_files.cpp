// Non-regular inputs are never read without bound: devices (/dev/zero, /dev/urandom) are refused
// by type, pipes are read up to a limit, and the size of a regular transform file is checked
// before it is read. Clouds and transforms (--initial / --ground-truth) alike.
#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
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

// The reader held about twice what it may read (a doubling buffer and its old copy: 2 GB
// resident for the 1 GiB limit). Now the stream is kept in chunks until it ends: the peak is the
// limit plus a chunk. Run in a child process, whose peak resident size (getrusage) is its own.
TEST_CASE("A cloud FIFO that never ends is refused at 1 GiB with bounded memory",
          "[io][non_regular]") {
  io_test::TempDir dir;
  int report[2];
  REQUIRE(::pipe(report) == 0);
  const pid_t child = ::fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    ::close(report[0]);
    ppcr::PointCloud cloud;
    const ppcr::Status s = read_through_fifo(
        dir, "zeros.xyz", std::string(1 << 16, '\0'), true,
        [&](const std::string& path) { return ppcr::io::read_cloud(path, &cloud); });
    struct rusage usage {};
    ::getrusage(RUSAGE_SELF, &usage);
    const long values[2] = {static_cast<long>(s.code()), usage.ru_maxrss};  // KiB on Linux
    const bool named = s.message().find("more than 1073741824 bytes") != std::string::npos;
    const long all[3] = {values[0], values[1], named ? 1 : 0};
    const ssize_t written = ::write(report[1], all, sizeof all);
    ::_exit(written == static_cast<ssize_t>(sizeof all) ? 0 : 1);
  }
  ::close(report[1]);
  long got[3] = {-1, -1, -1};
  const ssize_t n = ::read(report[0], got, sizeof got);
  ::close(report[0]);
  int status = 0;
  ::waitpid(child, &status, 0);
  REQUIRE(n == static_cast<ssize_t>(sizeof got));
  CHECK(WIFEXITED(status));
  CHECK(got[0] == static_cast<long>(ppcr::StatusCode::kIoError));
  CHECK(got[2] == 1);
  const double peak_mib = static_cast<double>(got[1]) / 1024.0;
  INFO("peak resident " << peak_mib << " MiB");
#if defined(__SANITIZE_ADDRESS__)
  WARN("AddressSanitizer build: its shadow memory and quarantine inflate the peak; not checked");
#else
  CHECK(peak_mib <= 1024.0 + 64.0);
#endif
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
