// The content hash of cached and compared inputs: the model checks' cache
// key, the bench reference's model and scene keys, MPI ranks' scene
// fingerprints, GLDF's product id. XXH3 (64 bits, seed 0, xxHash's
// streaming form), which hashes a 10⁷-triangle model's 180 MB of geometry
// in tens of milliseconds where a byte-at-a-time hash took 0.2 s. Not
// cryptographic: it tells unchanged inputs from changed ones, not
// adversarial ones.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "photometry/vec3.h"

namespace gonio::io {

class ContentHash {
 public:
  ContentHash();
  ~ContentHash();
  ContentHash(const ContentHash&) = delete;
  ContentHash& operator=(const ContentHash&) = delete;

  void bytes(const void* data, std::size_t n);
  template <class T>
  void value(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes(&v, sizeof v);
  }
  // The count, then the elements' bytes.
  template <class T>
  void values(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    value(v.size());
    if (!v.empty()) bytes(v.data(), v.size() * sizeof(T));
  }
  // The length, then the characters.
  void text(std::string_view s) {
    value(s.size());
    bytes(s.data(), s.size());
  }
  void vec(const Vec3& v) {
    value(v.x);
    value(v.y);
    value(v.z);
  }
  // Of everything so far (more may follow).
  std::uint64_t digest() const;
  // digest() as 16 lower-case hex digits.
  std::string hex() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// The hash of one string of bytes, as 16 hex digits.
std::string content_hash_hex(std::string_view bytes);

// 16 lower-case hex digits, as hashes are written.
std::string to_hex(std::uint64_t v);

// A cache file's seal: the digest of all the bytes before it (8 bytes, this
// machine's order) appended to OUT; without_digest gives back the bytes
// before a seal that matches them, and nothing for a missing or wrong one.
void append_digest(std::string& out);
std::optional<std::string_view> without_digest(std::string_view bytes);

}  // namespace gonio::io
