#include "io/support/file_io.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

namespace gonio::io {
namespace {

std::string errno_text() { return std::strerror(errno); }

}  // namespace

namespace {

// read_file's body for either container of bytes.
template <class Bytes>
Result<Bytes> read_whole(const std::string& path, std::size_t max_bytes) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return make_error(path, "cannot open: " + errno_text());
  if (S_ISDIR(st.st_mode)) return make_error(path, "is a directory, not a file");
  if (!S_ISREG(st.st_mode)) return make_error(path, "is not a regular file");
  if (static_cast<std::size_t>(st.st_size) > max_bytes)
    return make_error(path, "file too large (" + std::to_string(st.st_size) + " bytes, at most " +
                                std::to_string(max_bytes) + " accepted)");

  std::ifstream in(path, std::ios::binary);
  if (!in) return make_error(path, "cannot open: " + errno_text());
  Bytes bytes(static_cast<std::size_t>(st.st_size), 0);
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (in.gcount() != static_cast<std::streamsize>(bytes.size()))
    return make_error(path, "read error");
  return bytes;
}

}  // namespace

Result<std::string> read_file(const std::string& path, std::size_t max_bytes) {
  return read_whole<std::string>(path, max_bytes);
}

Result<std::vector<unsigned char>> read_file_bytes(const std::string& path, std::size_t max_bytes) {
  return read_whole<std::vector<unsigned char>>(path, max_bytes);
}

Status write_file_atomic(const std::string& path, std::string_view bytes) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::random_device rd;
  const std::string tmp =
      (dir / ("." + target.filename().string() + ".tmp" + std::to_string(rd() % 1000000))).string();

  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) return make_error(path, "cannot write: " + errno_text());
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      const std::string why = errno_text();
      ::close(fd);
      ::unlink(tmp.c_str());
      return make_error(path, "cannot write: " + why);
    }
    done += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0 || ::close(fd) != 0) {
    const std::string why = errno_text();
    ::unlink(tmp.c_str());
    return make_error(path, "cannot write: " + why);
  }
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string why = errno_text();
    ::unlink(tmp.c_str());
    return make_error(path, "cannot write: " + why);
  }
  return Ok{};
}

bool same_file(const std::string& a, const std::string& b) {
  std::error_code ec;
  const bool same = std::filesystem::equivalent(a, b, ec);
  return !ec && same;
}

Status make_directories(const std::string& path) {
  std::error_code ec;
  std::filesystem::create_directories(path, ec);
  if (ec) return make_error(path, "cannot create directory: " + ec.message());
  if (!std::filesystem::is_directory(path)) return make_error(path, "is not a directory");
  return Ok{};
}

}  // namespace gonio::io
