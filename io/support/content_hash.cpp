#include "io/support/content_hash.h"

#include <cstdio>
#include <cstring>
#include <new>

// Header-only use of Debian's libxxhash-dev: the functions are compiled
// here, inline, and nothing else includes xxhash.h.
#define XXH_INLINE_ALL
#include <xxhash.h>

namespace gonio::io {

struct ContentHash::State {
  XXH3_state_t xxh;  // 64-byte aligned: allocated with C++17's aligned new
};

ContentHash::ContentHash() : state_(std::make_unique<State>()) {
  if (XXH3_64bits_reset(&state_->xxh) != XXH_OK) throw std::bad_alloc();
}

ContentHash::~ContentHash() = default;

void ContentHash::bytes(const void* data, std::size_t n) {
  if (n > 0) XXH3_64bits_update(&state_->xxh, data, n);
}

std::uint64_t ContentHash::digest() const { return XXH3_64bits_digest(&state_->xxh); }

std::string ContentHash::hex() const { return to_hex(digest()); }

std::string to_hex(std::uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

std::string content_hash_hex(std::string_view bytes) {
  ContentHash h;
  h.bytes(bytes.data(), bytes.size());
  return h.hex();
}

void append_digest(std::string& out) {
  ContentHash all;
  all.bytes(out.data(), out.size());
  const std::uint64_t d = all.digest();
  out.append(reinterpret_cast<const char*>(&d), sizeof d);
}

std::optional<std::string_view> without_digest(std::string_view bytes) {
  std::uint64_t stored = 0;
  if (bytes.size() < sizeof stored) return std::nullopt;
  const std::string_view before = bytes.substr(0, bytes.size() - sizeof stored);
  std::memcpy(&stored, bytes.data() + before.size(), sizeof stored);
  ContentHash all;
  all.bytes(before.data(), before.size());
  if (all.digest() != stored) return std::nullopt;
  return before;
}

}  // namespace gonio::io
