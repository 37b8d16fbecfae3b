// Plain values to and from bytes, in this machine's representation: the
// caches' files, the CAD model cache, the messages between MPI ranks, and
// TM-25's numbers. The one set of helpers for them. A file whose format fixes
// the byte order asserts that the machine's is that one (TM-25 and the caches
// are little-endian: static_assert(std::endian::native == ...)).
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace gonio::io {

// Appends the value's bytes.
template <class T>
void append_bytes(std::string& out, const T& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

// Appends the elements' bytes (no count: the caller writes one where needed).
template <class T>
void append_all_bytes(std::string& out, const std::vector<T>& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  if (!v.empty()) out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

// Reads back what append_bytes wrote; each read fails (false, nothing read,
// the place kept) where fewer bytes are left than it needs.
class ByteReader {
 public:
  explicit ByteReader(std::string_view bytes) : bytes_(bytes) {}
  template <class T>
  bool get(T* v) {
    static_assert(std::is_trivially_copyable_v<T>);
    if (bytes_.size() - at_ < sizeof(T)) return false;
    std::memcpy(v, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return true;
  }
  // N elements (N checked against the bytes left before anything is sized).
  template <class T>
  bool get_all(std::vector<T>* v, std::uint64_t n) {
    static_assert(std::is_trivially_copyable_v<T>);
    if (n > (bytes_.size() - at_) / sizeof(T)) return false;
    v->resize(static_cast<std::size_t>(n));
    if (n > 0) std::memcpy(v->data(), bytes_.data() + at_, static_cast<std::size_t>(n) * sizeof(T));
    at_ += static_cast<std::size_t>(n) * sizeof(T);
    return true;
  }
  // Moves on N bytes, or to the end.
  void skip(std::size_t n) { at_ = n < bytes_.size() - at_ ? at_ + n : bytes_.size(); }
  std::size_t at() const { return at_; }

 private:
  std::string_view bytes_;
  std::size_t at_ = 0;
};

}  // namespace gonio::io
