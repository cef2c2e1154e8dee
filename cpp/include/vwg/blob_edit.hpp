// Element writes to a blob attribute during λ without copying the whole array (a robot's map
// changes in a few hundred cells a frame, and copying it per robot per frame dominated the frame).
// The engine lets λ write in place into the blobs of its own string and keeps the old value of
// every changed element in a BlobJournal, so a frame that fails is undone (a frame is all or
// nothing). Anywhere else an edit writes to a private copy, as ActorState::mutable_blob does.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "vwg/blob.hpp"

namespace vwg {

/// The old bytes of every element a frame changed in place, to put back if the frame fails.
class BlobJournal {
 public:
  /// Remember `size` (at most 8) bytes at `offset` of `blob`, about to be overwritten.
  void record(Blob& blob, std::size_t offset, const void* old, std::size_t size);
  /// Put every recorded element back, newest first, and forget them.
  void rollback();
  /// Take over `other`'s records, as if made after this journal's (a journal per thread, merged).
  void absorb(BlobJournal&& other);
  /// Forget the records (the frame was committed).
  void clear() { entries_.clear(); }
  std::size_t size() const { return entries_.size(); }

 private:
  struct Entry {
    Blob* blob;
    std::size_t offset;
    std::uint64_t old;
    std::size_t size;
  };
  std::vector<Entry> entries_;
};

/// Writes to the elements of one blob, recorded in a journal when there is one. Obtained from
/// ActorState::edit_blob, or made directly over a blob the caller owns alone.
template <class T>
class BlobEdit {
  static_assert(sizeof(T) <= 8);

 public:
  explicit BlobEdit(Blob& blob, BlobJournal* journal = nullptr)
      : blob_(&blob), cells_(reinterpret_cast<T*>(const_cast<std::byte*>(blob.data()))), journal_(journal) {}

  const Blob& blob() const { return *blob_; }
  std::size_t size() const { return blob_->size(); }
  std::span<const T> view() const { return {cells_, blob_->size()}; }
  T operator[](std::size_t k) const { return cells_[k]; }
  /// Set element k (flat, C order); writing the value it already has changes nothing.
  void set(std::size_t k, T value) {
    T& cell = cells_[k];
    if (cell == value) return;
    if (journal_) journal_->record(*blob_, k * sizeof(T), &cell, sizeof(T));
    cell = value;
    blob_->note_written_at(k * sizeof(T));
  }
  /// See Blob::reshare (the pages these writes made private that are equal to the shared ones again).
  std::size_t reshare() { return blob_->reshare(); }

 private:
  Blob* blob_;
  T* cells_;
  BlobJournal* journal_;
};

}  // namespace vwg
