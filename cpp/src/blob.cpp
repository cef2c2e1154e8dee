#include "vwg/blob.hpp"

#include <atomic>
#include <algorithm>
#include <cstring>
#include <limits>
#include <string>

#include "src/unique_number.hpp"
#include "vwg/error.hpp"
#include "vwg/hash.hpp"

namespace vwg {

std::size_t dtype_size(DType dtype) {
  switch (dtype) {
    case DType::Int8:
    case DType::UInt8:
      return 1;
    case DType::Int16:
      return 2;
    case DType::Int32:
    case DType::Float32:
      return 4;
    case DType::Int64:
    case DType::Float64:
      return 8;
  }
  return 1;
}

std::string_view dtype_name(DType dtype) {
  switch (dtype) {
    case DType::Int8: return "int8";
    case DType::UInt8: return "uint8";
    case DType::Int16: return "int16";
    case DType::Int32: return "int32";
    case DType::Int64: return "int64";
    case DType::Float32: return "float32";
    case DType::Float64: return "float64";
  }
  return "?";
}

DType dtype_from_name(std::string_view name) {
  for (DType d : {DType::Int8, DType::UInt8, DType::Int16, DType::Int32, DType::Int64,
                  DType::Float32, DType::Float64}) {
    if (dtype_name(d) == name) return d;
  }
  throw SchemaError("dtype", "unknown dtype '" + std::string(name) +
                                 "'; expected int8, uint8, int16, int32, int64, float32 or float64");
}

namespace {
struct BlobRevisions;
std::uint64_t new_revision() { return next_unique_number<BlobRevisions>(); }

std::size_t element_count(const std::vector<std::int64_t>& shape) {
  if (shape.size() > 4) throw SchemaError("shape", "a blob has at most 4 dimensions");
  std::size_t n = 1;
  for (std::int64_t extent : shape) {
    if (extent < 0) throw SchemaError("shape", "negative extent " + std::to_string(extent));
    n *= static_cast<std::size_t>(extent);
  }
  return n;
}
}  // namespace

Blob::Blob(DType dtype, std::vector<std::int64_t> shape)
    : dtype_(dtype), shape_(std::move(shape)), size_(element_count(shape_)),
      bytes_(size_ * dtype_size(dtype)), revision_(new_revision()) {}

void Blob::note_written() {
  bytes_.note_written();
  hash_valid_.store(false, std::memory_order_relaxed);
  revision_ = new_revision();
  if (log_) log_->restart(revision_);
}

void Blob::note_written_at(std::size_t offset) {
  bytes_.note_written(offset);
  hash_valid_.store(false, std::memory_order_relaxed);
  const std::uint64_t before = revision_;
  revision_ = new_revision();
  const std::size_t element = offset / dtype_size(dtype_);
  if (!log_) {
    log_ = std::make_unique<EditLog>();
    log_->ring.resize(std::max<std::size_t>(1, std::min(kLoggedWrites, size_)));
    log_->from_revision = before;
    log_->history = EditLog::next_history();
  }
  if (element > std::numeric_limits<std::uint32_t>::max()) {  // not loggable: as a write of the whole
    log_->restart(revision_);
    return;
  }
  log_->ring[log_->edits % log_->ring.size()] = static_cast<std::uint32_t>(element);
  ++log_->edits;
}

std::uint64_t Blob::EditLog::next_history() { return next_unique_number<EditLog>(); }

std::unique_ptr<Blob::EditLog> Blob::copy_log() const {
  if (!log_) return nullptr;
  auto copy = std::make_unique<EditLog>(*log_);
  // From here on the copy's writes and the original's differ: a mark the copy takes later is not
  // one of the original's, nor the reverse; a mark of the original up to here holds for both.
  copy->parent = log_->history;
  copy->forked_at = log_->edits;
  copy->history = EditLog::next_history();
  return copy;
}

Blob::Blob(DType dtype, std::vector<std::int64_t> shape, const void* data, std::size_t nbytes)
    : Blob(dtype, std::move(shape)) {
  if (nbytes != bytes_.size()) {
    throw SchemaError("blob", "got " + std::to_string(nbytes) + " bytes, expected " +
                                  std::to_string(bytes_.size()) + " for this dtype and shape");
  }
  if (nbytes) std::memcpy(bytes_.data(), data, nbytes);
}

void Blob::share() { bytes_.share(); }

std::uint64_t Blob::content_hash() const {
  if (!hash_valid_.load(std::memory_order_acquire)) {
    std::uint64_t h = hash_combine(0x766567ULL, static_cast<std::uint64_t>(dtype_));
    for (std::int64_t extent : shape_) h = hash_combine(h, static_cast<std::uint64_t>(extent));
    hash_.store(hash_bytes(bytes_.data(), bytes_.size(), h), std::memory_order_relaxed);
    hash_valid_.store(true, std::memory_order_release);
  }
  return hash_.load(std::memory_order_relaxed);
}

bool Blob::same_content(const Blob& other) const {
  if (this == &other) return true;
  return dtype_ == other.dtype_ && shape_ == other.shape_ && nbytes() == other.nbytes() &&
         (nbytes() == 0 || std::memcmp(data(), other.data(), nbytes()) == 0);
}

Blob::Blob(const Blob& other)
    : dtype_(other.dtype_), shape_(other.shape_), size_(other.size_), bytes_(other.bytes_), revision_(other.revision_),
      log_(other.copy_log()) {
  if (other.hash_valid_.load(std::memory_order_acquire)) {
    hash_.store(other.hash_.load(std::memory_order_relaxed), std::memory_order_relaxed);
    hash_valid_.store(true, std::memory_order_relaxed);
  }
}

std::shared_ptr<Blob> Blob::clone() const { return std::make_shared<Blob>(*this); }

}  // namespace vwg
