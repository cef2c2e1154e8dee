// An array that reads a fill value wherever it was never written, made by zeroing its memory.
//
// Not part of vwg's API (vwg/detail/): installed only because
// plan::DStarLite (vwg/plan/dstar_lite.hpp) holds them by value.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <cstring>
#include <memory>
#include <new>
#include <type_traits>

#include "vwg/state.hpp"

namespace vwg::plan {

/// A fixed-size array of T (a trivially copyable type of 4 or 8 bytes) whose elements read `fill`
/// until they are written: each element is stored as its bits XOR fill's, in memory from calloc,
/// which zeroes it faster than a loop writes the fill value (D* Lite's g, rhs and queue positions:
/// 12 or 20 bytes a cell, 3 or 5 MB for 512 × 512, made anew for every plan).
template <class T>
class FilledArray {
  static_assert(std::is_trivially_copyable_v<T> && (sizeof(T) == 4 || sizeof(T) == 8));
  using Bits = std::conditional_t<sizeof(T) == 8, std::uint64_t, std::uint32_t>;

 public:
  FilledArray() = default;
  FilledArray(std::size_t size, T fill) : fill_(std::bit_cast<Bits>(fill)), size_(size), bits_(allocate(size)) {}
  FilledArray(const FilledArray& other) : fill_(other.fill_), size_(other.size_), bits_(allocate(other.size_)) {
    if (size_ > 0) std::memcpy(bits_.get(), other.bits_.get(), size_ * sizeof(Bits));
  }
  FilledArray& operator=(const FilledArray& other) {
    if (this != &other) *this = FilledArray(other);
    return *this;
  }
  FilledArray(FilledArray&&) noexcept = default;
  FilledArray& operator=(FilledArray&&) noexcept = default;

  T operator[](std::size_t i) const { return std::bit_cast<T>(static_cast<Bits>(bits_[i] ^ fill_)); }
  void set(std::size_t i, T value) { bits_[i] = static_cast<Bits>(std::bit_cast<Bits>(value) ^ fill_); }
  std::size_t size() const { return size_; }

  /// For a saved run (vwg/state.hpp): the fill and the stored bits.
  void save(StateWriter& out) const {
    out.u64(fill_);
    out.u64(size_);
    out.raw(bits_.get(), size_ * sizeof(Bits));
  }
  /// An array of `expected` elements, as save() wrote it.
  static FilledArray load(StateReader& in, std::size_t expected) {
    FilledArray a;
    a.fill_ = static_cast<Bits>(in.u64());
    const std::size_t size = in.count(sizeof(Bits), "array elements");
    if (size != expected) in.fail("an array of " + std::to_string(size) + " elements where " + std::to_string(expected) + " belong");
    a.size_ = size;
    a.bits_ = allocate(size);
    in.raw(a.bits_.get(), size * sizeof(Bits), "array elements");
    return a;
  }

 private:
  // calloc, not mmap for large arrays: on a virtual machine a page fault per 4 KB cost more than
  // zeroing (D* Lite's first plans on 512 × 512 maps took 1.4-3× longer).
  struct Free {
    void operator()(Bits* p) const { std::free(p); }
  };
  static std::unique_ptr<Bits[], Free> allocate(std::size_t size) {
    auto* p = static_cast<Bits*>(std::calloc(size > 0 ? size : 1, sizeof(Bits)));
    if (p == nullptr) throw std::bad_alloc();
    return std::unique_ptr<Bits[], Free>(p);
  }

  Bits fill_ = 0;
  std::size_t size_ = 0;
  std::unique_ptr<Bits[], Free> bits_;
};

}  // namespace vwg::plan
