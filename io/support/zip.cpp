// The only file that includes libzip (see io/support/zip.h).
#include "io/support/zip.h"

#include <cstdio>
#include <ctime>
#include <memory>
#include <set>

#include <zip.h>

namespace gonio::io {
namespace {

struct ArchiveCloser {
  void operator()(zip_t* z) const { zip_discard(z); }
};
struct FileCloser {
  void operator()(zip_file_t* f) const { zip_fclose(f); }
};

std::string quoted(std::string_view s) {
  std::string out = "'";
  for (char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", u);
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "'";
}

}  // namespace

bool is_safe_entry_name(std::string_view name) {
  if (name.empty() || name.front() == '/' || name.find('\\') != std::string_view::npos ||
      name.find('\0') != std::string_view::npos)
    return false;
  if (name.size() >= 2 && name[1] == ':') return false;  // C:...
  std::size_t start = 0;
  while (start <= name.size()) {
    const std::size_t end = std::min(name.find('/', start), name.size());
    const std::string_view part = name.substr(start, end - start);
    if (part == ".." || part == ".") return false;
    if (part.empty() && end != name.size()) return false;  // "a//b"
    start = end + 1;
  }
  return true;
}

Result<std::vector<ZipEntry>> read_zip(std::string_view bytes, const std::string& name,
                                       const ZipLimits& limits) {
  zip_error_t error;
  zip_error_init(&error);
  zip_source_t* source = zip_source_buffer_create(bytes.data(), bytes.size(), 0, &error);
  if (!source) {
    const std::string message = zip_error_strerror(&error);
    zip_error_fini(&error);
    return make_error(name, "not a readable ZIP archive: " + message);
  }
  std::unique_ptr<zip_t, ArchiveCloser> archive(zip_open_from_source(source, ZIP_RDONLY, &error));
  if (!archive) {
    const std::string message = zip_error_strerror(&error);
    zip_error_fini(&error);
    zip_source_free(source);
    return make_error(name, "not a readable ZIP archive: " + message);
  }
  zip_error_fini(&error);

  const zip_int64_t count = zip_get_num_entries(archive.get(), 0);
  if (count < 0) return make_error(name, "not a readable ZIP archive");
  if (static_cast<std::size_t>(count) > limits.max_entries)
    return make_error(name, "archive has " + std::to_string(count) + " entries, at most " +
                                std::to_string(limits.max_entries) + " accepted");
  // Names and declared sizes first: nothing is inflated from an archive
  // that is refused.
  std::set<std::string> seen;
  std::size_t declared_total = 0;
  std::vector<std::pair<zip_uint64_t, zip_stat_t>> files;
  for (zip_int64_t i = 0; i < count; ++i) {
    zip_stat_t st;
    zip_stat_init(&st);
    if (zip_stat_index(archive.get(), static_cast<zip_uint64_t>(i), 0, &st) != 0 ||
        !(st.valid & ZIP_STAT_NAME) || !(st.valid & ZIP_STAT_SIZE))
      return make_error(name, "entry " + std::to_string(i) + " cannot be read: " +
                                  zip_strerror(archive.get()));
    const std::string entry = st.name;
    if (!entry.empty() && entry.back() == '/') {
      if (!is_safe_entry_name(entry.substr(0, entry.size() - 1)))
        return make_error(name, "entry " + quoted(entry) +
                                    " leaves the archive (absolute name or '..'); refused");
      continue;  // a directory
    }
    if (!is_safe_entry_name(entry))
      return make_error(name, "entry " + quoted(entry) +
                                  " leaves the archive (absolute name or '..'); refused");
    if (!seen.insert(entry).second)
      return make_error(name, "entry " + quoted(entry) + " appears twice");
    if (st.size > limits.max_entry_bytes)
      return make_error(name, "entry " + quoted(entry) + " declares " + std::to_string(st.size) +
                                  " bytes, at most " + std::to_string(limits.max_entry_bytes) +
                                  " accepted");
    declared_total += static_cast<std::size_t>(st.size);
    if (declared_total > limits.max_total_bytes)
      return make_error(name, "entries declare more than " + std::to_string(limits.max_total_bytes) +
                                  " bytes in all; refused");
    files.emplace_back(static_cast<zip_uint64_t>(i), st);
  }

  std::vector<ZipEntry> out;
  out.reserve(files.size());
  for (const auto& [index, st] : files) {
    std::unique_ptr<zip_file_t, FileCloser> file(zip_fopen_index(archive.get(), index, 0));
    if (!file)
      return make_error(name, "entry " + quoted(st.name) + " cannot be opened: " + zip_strerror(archive.get()));
    ZipEntry entry{st.name, std::string()};
    const std::size_t declared = static_cast<std::size_t>(st.size);
    entry.bytes.resize(declared + 1);  // one byte more shows a lie
    std::size_t got = 0;
    while (got < entry.bytes.size()) {
      const zip_int64_t n = zip_fread(file.get(), entry.bytes.data() + got, entry.bytes.size() - got);
      if (n < 0)
        return make_error(name, "entry " + quoted(st.name) + " is corrupt: " + zip_file_strerror(file.get()));
      if (n == 0) break;
      got += static_cast<std::size_t>(n);
    }
    if (got > declared)
      return make_error(name, "entry " + quoted(st.name) + " inflates beyond the " + std::to_string(declared) +
                                  " bytes it declares (a zip bomb?); refused");
    if (got < declared)
      return make_error(name, "entry " + quoted(st.name) + " is truncated: " + std::to_string(got) + " of " +
                                  std::to_string(declared) + " bytes");
    entry.bytes.resize(got);
    out.push_back(std::move(entry));
  }
  return out;
}

Result<std::string> write_zip(const std::vector<ZipEntry>& entries, std::int64_t mtime_unix) {
  std::set<std::string> seen;
  for (const ZipEntry& e : entries) {
    if (!is_safe_entry_name(e.name)) return make_error(e.name, "unsafe archive entry name");
    if (!seen.insert(e.name).second) return make_error(e.name, "archive entry name given twice");
  }
  zip_error_t error;
  zip_error_init(&error);
  zip_source_t* buffer = zip_source_buffer_create(nullptr, 0, 0, &error);
  if (!buffer) {
    zip_error_fini(&error);
    return make_error("", "cannot create an archive in memory");
  }
  zip_source_keep(buffer);
  zip_t* archive = zip_open_from_source(buffer, ZIP_TRUNCATE, &error);
  zip_error_fini(&error);
  if (!archive) {
    zip_source_free(buffer);
    return make_error("", "cannot create an archive in memory");
  }
  const auto fail = [&](const std::string& what) {
    const std::string message = what + ": " + zip_strerror(archive);
    zip_discard(archive);
    zip_source_free(buffer);
    return make_error("", message);
  };
  for (const ZipEntry& e : entries) {
    zip_source_t* s = zip_source_buffer(archive, e.bytes.data(), e.bytes.size(), 0);
    if (!s) return fail("cannot add " + e.name);
    const zip_int64_t index = zip_file_add(archive, e.name.c_str(), s, ZIP_FL_ENC_UTF_8);
    if (index < 0) {
      zip_source_free(s);
      return fail("cannot add " + e.name);
    }
    if (zip_set_file_compression(archive, static_cast<zip_uint64_t>(index), ZIP_CM_DEFLATE, 9) != 0 ||
        zip_file_set_mtime(archive, static_cast<zip_uint64_t>(index), static_cast<time_t>(mtime_unix), 0) != 0)
      return fail("cannot set up " + e.name);
  }
  if (zip_close(archive) != 0) return fail("cannot write the archive");

  std::string out;
  if (zip_source_open(buffer) != 0) {
    zip_source_free(buffer);
    return make_error("", "cannot read the archive back from memory");
  }
  char chunk[1 << 16];
  zip_int64_t n = 0;
  while ((n = zip_source_read(buffer, chunk, sizeof chunk)) > 0) out.append(chunk, static_cast<std::size_t>(n));
  zip_source_close(buffer);
  zip_source_free(buffer);
  if (n < 0) return make_error("", "cannot read the archive back from memory");
  return out;
}

}  // namespace gonio::io
