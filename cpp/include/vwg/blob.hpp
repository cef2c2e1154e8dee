// A large attribute value (an occupancy grid, an image, a path): an n-dimensional array held by
// reference from the world string, shared between frames and copied only when written
// (DESIGN.md choice 4).
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "vwg/detail/shared_pages.hpp"

namespace vwg {

enum class DType : std::uint8_t { Int8, UInt8, Int16, Int32, Int64, Float32, Float64 };

/// Size in bytes of one element of `dtype`.
std::size_t dtype_size(DType dtype);
/// numpy-style name: "int8", "uint8", ..., "float64".
std::string_view dtype_name(DType dtype);
/// Inverse of dtype_name; throws vwg::SchemaError for an unknown name.
DType dtype_from_name(std::string_view name);

/// An owned, contiguous, C-ordered array. Once a Blob is shared (held by a string, a snapshot or
/// Python), it is treated as immutable: writers go through copy-on-write (ActorState::mutable_blob).
class Blob {
 public:
  /// A zero-filled array of the given type and shape (each extent >= 0, at most 4 dimensions).
  Blob(DType dtype, std::vector<std::int64_t> shape);
  /// An array initialised from `nbytes` bytes at `data`; `nbytes` must match dtype and shape.
  Blob(DType dtype, std::vector<std::int64_t> shape, const void* data, std::size_t nbytes);
  /// A copy: the same content, revision and hash (see clone()).
  Blob(const Blob& other);
  Blob& operator=(const Blob&) = delete;

  DType dtype() const { return dtype_; }
  std::span<const std::int64_t> shape() const { return shape_; }
  std::size_t ndim() const { return shape_.size(); }
  std::size_t size() const { return size_; }  ///< number of elements
  std::size_t nbytes() const { return bytes_.size(); }
  const std::byte* data() const { return bytes_.data(); }
  /// Write access; forgets the cached hash. Only the sole owner may write (see class comment).
  std::byte* mutable_data() {
    note_written();
    return bytes_.data();
  }
  /// Call after writing through a pointer taken earlier: forgets the cached hash and takes a new
  /// revision.
  void note_written();
  /// note_written() for the element at byte `offset` alone (reshare() then looks at its page only),
  /// remembered in the blob's log of element writes (see written_since).
  void note_written_at(std::size_t offset);
  /// Give back to the shared content the pages written since the last call that are equal to it
  /// again (SharedPages::reshare); returns how many. Changes no byte, so no revision either.
  std::size_t reshare() { return bytes_.reshare(); }
  /// Let copies share the memory pages they and this blob do not write (SharedPages): for a large
  /// array that many actors start from, such as the known map every robot copies. Changes no byte,
  /// but moves them: call it before anyone holds a pointer to them (a BlobEdit, a numpy view).
  void share();
  /// Whether copies share pages with this blob (share() was called on it or on what it copies).
  bool shared() const { return bytes_.shared(); }
  /// The pages whose content differs from what the blob was shared as (0 for a blob never shared).
  std::size_t private_pages() const { return bytes_.private_pages(); }
  /// The content it was shared as (empty if never shared), and who made it (SharedPages::origin):
  /// what is worked out from that content once serves every copy (OriginCache).
  template <class T>
  std::span<const T> original_view() const {
    const std::span<const std::byte> b = bytes_.original();
    return {reinterpret_cast<const T*>(b.data()), b.size() / sizeof(T)};
  }
  std::weak_ptr<const void> origin() const { return bytes_.origin(); }
  /// A number that changes whenever the content may have changed and is never reused by another
  /// content: equal revisions mean equal content (a copy keeps its original's until written).
  /// Cheaper than content_hash() to tell whether a blob changed since it was last looked at.
  std::uint64_t revision() const { return revision_; }

  /// Where the blob's content stands now, to ask later which elements were written since
  /// (written_since).
  struct Mark {
    std::uint64_t revision = 0;
    std::uint64_t edits = 0;    // element writes logged when the mark was taken
    std::uint64_t history = 0;  // whose log counted them
  };
  Mark mark() const { return log_ ? Mark{revision_, log_->edits, log_->history} : Mark{revision_, 0, 0}; }
  /// Calls each(k) for the flat index k of every element written (note_written_at) since `then`, a
  /// mark of this blob or of the blob it was copied from (taken before the copy), oldest first; an
  /// element written twice comes twice, and one written back to its old value comes too. Returns
  /// false, calling nothing, when the blob cannot tell: it was written whole since (note_written),
  /// `then` marks another history, or more than kLoggedWrites writes were made since. For a reader
  /// that keeps something worked out from a large blob (a planner's grids of a robot's map) and
  /// follows the few elements that change instead of comparing a copy of the whole blob.
  template <class Each>
  bool written_since(const Mark& then, Each&& each) const {
    if (then.revision == revision_) return true;
    if (!log_ || !log_->holds(then)) return false;
    for (std::uint64_t k = then.edits; k < log_->edits; ++k) each(std::size_t{log_->ring[k % log_->ring.size()]});
    return true;
  }
  /// How many element writes the log keeps at most (fewer for a smaller blob: its size). A robot
  /// in a crowd of ten thousand writes 2,000-4,000 cells of its map between two looks of its
  /// planner now and then (it waits for its motors while others pass).
  static constexpr std::size_t kLoggedWrites = 8192;

  template <class T>
  std::span<const T> view() const {
    return {reinterpret_cast<const T*>(bytes_.data()), size_};
  }
  template <class T>
  std::span<T> mutable_view() {
    return {reinterpret_cast<T*>(mutable_data()), size_};
  }

  /// A stable 64-bit hash of dtype, shape and bytes; the blob's name in the text form (`@hex`).
  std::uint64_t content_hash() const;
  /// Same dtype, shape and bytes.
  bool same_content(const Blob& other) const;
  std::shared_ptr<Blob> clone() const;

 private:
  DType dtype_;
  std::vector<std::int64_t> shape_;
  std::size_t size_ = 0;
  SharedPages bytes_;
  // The hash, computed when first asked for; atomics, since the threads of a frame may ask for the
  // hash of a blob several actors share (any two compute the same value).
  mutable std::atomic<std::uint64_t> hash_{0};
  mutable std::atomic<bool> hash_valid_{false};
  std::uint64_t revision_;
  // The last element writes, made when the first is: most blobs are never written by element.
  struct EditLog {
    std::vector<std::uint32_t> ring;  // the element of write k at k % ring.size()
    std::uint64_t edits = 0;          // element writes so far
    std::uint64_t from = 0, from_revision = 0;  // the log is whole from write `from` on, made at that revision
    // Which history the writes belong to: a copy's writes are its own from the copy on (write
    // `forked_at` of the original's history, `parent`).
    std::uint64_t history = 0, parent = 0, forked_at = 0;
    /// What the log knows stops here (the blob was written whole): it starts again from this
    /// content, a history of its own.
    void restart(std::uint64_t revision) {
      from = edits;
      from_revision = revision;
      history = next_history();
      parent = forked_at = 0;
    }
    static std::uint64_t next_history();
    bool holds(const Mark& then) const {
      if (then.edits < from || then.edits > edits || edits - then.edits > ring.size()) return false;
      if (then.edits == from) return then.revision == from_revision;  // equal revisions: equal content
      return then.history == history || (then.history == parent && then.edits <= forked_at);
    }
  };
  std::unique_ptr<EditLog> copy_log() const;
  std::unique_ptr<EditLog> log_;
};

}  // namespace vwg
