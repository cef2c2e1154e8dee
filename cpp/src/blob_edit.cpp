#include "vwg/blob_edit.hpp"

#include <cstring>

namespace vwg {

void BlobJournal::record(Blob& blob, std::size_t offset, const void* old, std::size_t size) {
  Entry e{&blob, offset, 0, size};
  std::memcpy(&e.old, old, size);
  entries_.push_back(e);
}

void BlobJournal::absorb(BlobJournal&& other) {
  entries_.insert(entries_.end(), other.entries_.begin(), other.entries_.end());
  other.entries_.clear();
}

void BlobJournal::rollback() {
  for (auto it = entries_.rbegin(); it != entries_.rend(); ++it) {
    std::memcpy(it->blob->mutable_data() + it->offset, &it->old, it->size);
  }
  entries_.clear();
}

}  // namespace vwg
