// Bytes whose copies share the memory pages they have not written (DESIGN.md choice 4 at the page
// level). Ten thousand robots each hold a map and planning grids of a large map; as plain arrays
// that is tens of megabytes a robot, though each robot changes a few hundred cells of it. A buffer
// that was share()d holds its content in an in-memory file (memfd) mapped privately: its copies
// map the same file privately too, and the kernel copies a page only when one of them writes it.
// Readers still see one contiguous array.
//
// Not part of vwg's API (vwg/detail/): installed only because
// Blob (vwg/blob.hpp) and geometry::BlockedGrid hold them by value.
#pragma once

#include <cstddef>
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <memory>
#include <mutex>
#include <span>
#include <type_traits>
#include <utility>
#include <vector>

namespace vwg {

class SharedPages {
 public:
  /// Below this many bytes share() keeps the buffer as it is: a page table entry and a file per
  /// copy cost more than a small copy.
  static constexpr std::size_t kMinShared = 64 * 1024;

  SharedPages() = default;
  /// `size` zero bytes, on the heap.
  explicit SharedPages(std::size_t size);
  /// The same bytes: the pages `other` has not written since it was shared stay shared with it;
  /// a buffer never shared is copied, and so is a shared one when the mapping budget is spent or
  /// the system refuses another mapping (see mapping_budget).
  SharedPages(const SharedPages& other);
  SharedPages& operator=(const SharedPages& other);
  SharedPages(SharedPages&& other) noexcept;
  SharedPages& operator=(SharedPages&& other) noexcept;
  ~SharedPages();

  std::size_t size() const { return size_; }
  const std::byte* data() const { return data_; }
  /// Write access to any byte: the next reshare() looks at every page, and the next copies compare
  /// every page with the shared content (still sharing the pages found equal).
  std::byte* data() {
    note_written();
    return data_;
  }
  /// Say that bytes anywhere were written through a pointer taken from the const data().
  void note_written() {
    pristine_ = false;
    written_all_ = true;
  }
  /// Say that the byte at `offset` was (or is about to be) written: only its page is looked at.
  void note_written(std::size_t offset) {
    pristine_ = false;
    if (base_ != nullptr) written_[offset / page_size() / 64] |= std::uint64_t{1} << (offset / page_size() % 64);
  }

  /// Put the content into an in-memory file and map it privately, so copies share its pages. Does
  /// nothing below kMinShared bytes, when the buffer already is shared and unwritten, or when the
  /// system refuses a file (then copies are plain copies: sharing saves memory, it changes no byte).
  /// The content moves: call it before handing out pointers to it.
  void share();
  /// Whether copies share pages with this buffer.
  bool shared() const { return base_ != nullptr; }
  /// The pages that differ from the content this buffer was shared as (a shared buffer), found by
  /// comparing them: what this buffer costs beyond the shared pages. 0 for a buffer never shared.
  std::size_t private_pages() const;
  /// Give back to the shared file the pages written since the last call whose content is again
  /// what it was when shared (a robot saw a passer-by, then saw it leave): memory stays flat over
  /// a long run. Returns how many it gave back. Changes no byte; reads only the pages written.
  std::size_t reshare();

  /// The content this buffer was shared as (empty if never shared): what copies start from.
  std::span<const std::byte> original() const;
  /// Who made that content: equal for a buffer and its copies while any of them lives (compare
  /// with owner_before or lock(): the content of an expired origin is gone).
  std::weak_ptr<const void> origin() const { return base_; }

  static std::size_t page_size();

  /// The memory mappings shared buffers hold now, in this process (a shared buffer and each of its
  /// copies hold one; the content they share, one more).
  static std::size_t mappings();
  /// At most this many: all but 4,096 of the system's vm.max_map_count (65,530 by default), so the
  /// rest of the process can still map memory (set_mapping_budget changes it, for tests). Past it,
  /// share() keeps a buffer plain and copies are plain copies (the same bytes, at their full
  /// size), and the log ("vwg.shared_pages" in Python) says so once.
  static std::size_t mapping_budget();
  static void set_mapping_budget(std::size_t mappings);

 private:
  struct File;  // the in-memory file a shared buffer maps: its content when shared, never written
  void release() noexcept;
  /// A private mapping of `file`, or nullptr if the system refuses one.
  static std::byte* map_private(const File& file);

  std::shared_ptr<const File> base_;  // set when shared
  std::byte* data_ = nullptr;
  std::size_t size_ = 0;
  bool pristine_ = false;  // shared and not written since: equal to base_'s content
  // Shared: the pages written since the last reshare(), a bit each, or all of them.
  std::vector<std::uint64_t> written_;
  bool written_all_ = false;
};

/// An array of trivially copyable T in SharedPages: the elements of a planning grid or a map's
/// bits that every robot starts from and changes in a few places.
template <class T>
class SharedArray {
  static_assert(std::is_trivially_copyable_v<T>);

 public:
  SharedArray() = default;
  /// `n` elements of value `fill` (zero bytes are not written: calloc's pages stay untouched).
  explicit SharedArray(std::size_t n, T fill = T{}) : bytes_(n * sizeof(T)) {
    static constexpr unsigned char kZero[sizeof(T)] = {};
    if (std::memcmp(&fill, kZero, sizeof(T)) != 0) std::fill_n(data(), n, fill);
  }
  std::size_t size() const { return bytes_.size() / sizeof(T); }
  bool empty() const { return size() == 0; }
  const T* data() const { return reinterpret_cast<const T*>(bytes_.data()); }
  /// Write access to every element (a bulk write: see SharedPages::data).
  T* data() { return reinterpret_cast<T*>(bytes_.data()); }
  const T& operator[](std::size_t i) const { return data()[i]; }
  /// Write one element (only its page is looked at by reshare()).
  void set(std::size_t i, const T& value) {
    bytes_.note_written(i * sizeof(T));
    const_cast<T*>(std::as_const(*this).data())[i] = value;
  }
  std::span<const T> span() const { return {data(), size()}; }
  void assign(std::size_t n, T fill) { *this = SharedArray(n, fill); }
  /// See SharedPages.
  void share() { bytes_.share(); }
  bool shared() const { return bytes_.shared(); }
  std::size_t private_pages() const { return bytes_.private_pages(); }
  std::size_t reshare() { return bytes_.reshare(); }

 private:
  SharedPages bytes_;
};

/// What is made once from a shared content and a key (the planning grids of the known map for a
/// robot's radius), kept while that content lives: every robot starts from a copy of it instead
/// of making its own. Safe to use from several threads; values are made under one lock (the
/// callers waiting want the same value, made once). An entry whose content is gone is dropped at
/// the next get().
template <class Key, class Value>
class OriginCache {
 public:
  /// The value for (origin, key), made by `make()` the first time; nullptr for an expired origin.
  template <class Make>
  std::shared_ptr<const Value> get(const std::weak_ptr<const void>& origin, const Key& key, Make&& make) {
    if (origin.expired()) return nullptr;
    const std::lock_guard<std::mutex> lock(mutex_);
    std::erase_if(entries_, [](const Entry& e) { return e.origin.expired(); });
    for (const Entry& e : entries_) {
      if (!e.origin.owner_before(origin) && !origin.owner_before(e.origin) && e.key == key) return e.value;
    }
    // Made under the lock: the robots asking at the same time want the same value, made once.
    entries_.push_back(Entry{origin, key, std::make_shared<const Value>(make())});
    return entries_.back().value;
  }

 private:
  struct Entry {
    std::weak_ptr<const void> origin;  // holds its control block, so no later content takes its place
    Key key;
    std::shared_ptr<const Value> value;
  };
  std::mutex mutex_;
  std::vector<Entry> entries_;
};

}  // namespace vwg
