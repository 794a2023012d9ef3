#pragma once
// SHA-256 (FIPS 180-4), for content hashes in run.json (the mission config's hash). Small and
// self-contained so the project needs no crypto dependency; not meant for secrets.
#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace rangecal {

/// Incremental SHA-256: update() any number of times, then digest() once.
class Sha256 {
 public:
  Sha256();
  void update(const void* data, std::size_t size);
  void update(std::string_view s) { update(s.data(), s.size()); }
  /// The 32-byte digest. Finalises the state: call once, after the last update().
  std::array<std::uint8_t, 32> digest();

 private:
  void compress(const std::uint8_t* block);
  std::array<std::uint32_t, 8> h_;
  std::array<std::uint8_t, 64> buffer_{};
  std::size_t buffered_ = 0;
  std::uint64_t total_bytes_ = 0;
};

/// SHA-256 of `data` as 64 lowercase hex digits.
std::string sha256_hex(std::string_view data);

}  // namespace rangecal
