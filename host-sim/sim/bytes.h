// Plain values to bytes and back, for a robot's state travelling between
// processes (host-sim/mpi). Both ends are the same build of the same
// program on machines of one byte order, so values are copied as they lie
// in memory.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <type_traits>
#include <vector>

namespace troupe::sim::bytes {

template <class T>
void put(std::vector<std::byte>& out, const T& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  const size_t at = out.size();
  out.resize(at + sizeof(T));
  std::memcpy(out.data() + at, &v, sizeof(T));
}

/// Its length (uint64_t), then its elements.
template <class T>
void put_vector(std::vector<std::byte>& out, const std::vector<T>& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  put(out, uint64_t(v.size()));
  const size_t at = out.size();
  out.resize(at + v.size() * sizeof(T));
  if (!v.empty()) std::memcpy(out.data() + at, v.data(), v.size() * sizeof(T));
}

/// Reads from the front of `in`, moving it on; false (nothing read) when
/// too few bytes are left.
template <class T>
bool get(std::span<const std::byte>& in, T& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  if (in.size() < sizeof(T)) return false;
  std::memcpy(&v, in.data(), sizeof(T));
  in = in.subspan(sizeof(T));
  return true;
}

/// What put_vector() wrote; false when the length does not fit in `in`.
template <class T>
bool get_vector(std::span<const std::byte>& in, std::vector<T>& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  uint64_t n = 0;
  std::span<const std::byte> at = in;
  if (!get(at, n) || n > at.size() / (sizeof(T) ? sizeof(T) : 1)) return false;
  v.resize(n);
  if (n) std::memcpy(v.data(), at.data(), n * sizeof(T));
  in = at.subspan(n * sizeof(T));
  return true;
}

}  // namespace troupe::sim::bytes
