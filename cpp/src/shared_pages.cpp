#include "vwg/detail/shared_pages.hpp"

#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <new>
#include <string>
#include <utility>

#include "vwg/log.hpp"

namespace vwg {

namespace {

std::size_t round_up(std::size_t n) {
  const std::size_t page = SharedPages::page_size();
  return (n + page - 1) / page * page;
}

std::size_t system_mapping_limit() {
  std::size_t limit = 0;
  std::ifstream in("/proc/sys/vm/max_map_count");
  return in >> limit && limit > 0 ? limit : 65530;  // Linux's default if it cannot be read
}

std::atomic<std::size_t>& mappings_held() {
  static std::atomic<std::size_t> held{0};
  return held;
}

std::atomic<std::size_t>& budget_of_mappings() {
  // All but 4,096 of what the system allows (half, if it allows less than 8,192): the rest of the
  // process (malloc, thread stacks, the interpreter and its modules: about 1,600 in a robot run,
  // a sanitizer) keeps room to map memory when the robots have taken their share.
  static std::atomic<std::size_t> budget{[] {
    const std::size_t limit = system_mapping_limit();
    return limit >= 8192 ? limit - 4096 : limit / 2;
  }()};
  return budget;
}

/// Said once: copies that follow cost their full size, which a user running more robots than the
/// limit allows would otherwise see only as memory running out.
void say_copies_are_plain(const std::string& why) {
  static std::atomic<bool> said{false};
  if (said.exchange(true)) return;
  log(LogLevel::Warning, "shared_pages",
      why + ": copies of shared arrays (robots' maps and planning grids) are plain copies from now on, each costing its "
            "full size. Each shared copy is a memory mapping (a robot holds 5 or 6); Linux allows vm.max_map_count of them "
            "per process (" + std::to_string(system_mapping_limit()) + " here) and vwg takes at most " +
            std::to_string(budget_of_mappings().load()) + ". Raise the limit (sysctl -w vm.max_map_count=262144) to run more "
            "robots in this memory.");
}

/// One more mapping of shared pages, if the budget allows it; give_back_mapping() when unmapped.
bool take_mapping() {
  if (mappings_held().fetch_add(1) < budget_of_mappings().load()) return true;
  mappings_held().fetch_sub(1);
  say_copies_are_plain("vwg's budget of memory mappings is spent");
  return false;
}

void give_back_mapping() { mappings_held().fetch_sub(1); }

/// mmap(), counted against the budget; nullptr if the budget or the system refuses.
std::byte* map_counted(int fd, std::size_t size, int protection, int flags) {
  if (!take_mapping()) return nullptr;
  void* p = mmap(nullptr, round_up(size), protection, flags, fd, 0);
  if (p != MAP_FAILED) return static_cast<std::byte*>(p);
  const int error = errno;
  give_back_mapping();
  say_copies_are_plain("the system refused another memory mapping (" + std::string(std::strerror(error)) + ")");
  return nullptr;
}

void unmap_counted(const void* p, std::size_t size) {
  munmap(const_cast<void*>(p), round_up(size));
  give_back_mapping();
}

}  // namespace

std::size_t SharedPages::mappings() { return mappings_held().load(); }
std::size_t SharedPages::mapping_budget() { return budget_of_mappings().load(); }
void SharedPages::set_mapping_budget(std::size_t mappings) { budget_of_mappings().store(mappings); }

/// An in-memory file holding a buffer's content as it was shared, and a read-only view of it (what
/// copies and reshare() compare pages with). Never written after it is made.
struct SharedPages::File {
  int fd = -1;
  std::size_t size = 0;
  const std::byte* view = nullptr;
  File() = default;
  File(const File&) = delete;
  File& operator=(const File&) = delete;
  ~File() {
    if (view != nullptr) unmap_counted(view, size);
    if (fd >= 0) close(fd);
  }
};

std::size_t SharedPages::page_size() {
  static const std::size_t page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  return page;
}

SharedPages::SharedPages(std::size_t size) : size_(size) {
  if (size == 0) return;
  data_ = static_cast<std::byte*>(std::calloc(size, 1));
  if (data_ == nullptr) throw std::bad_alloc();
}

std::byte* SharedPages::map_private(const File& file) { return map_counted(file.fd, file.size, PROT_READ | PROT_WRITE, MAP_PRIVATE); }

SharedPages::SharedPages(const SharedPages& other) : size_(other.size_) {
  if (size_ == 0) return;
  std::vector<std::uint64_t> written(other.written_.size(), 0);  // before mapping: nothing to undo if it throws
  std::byte* mapped = other.base_ != nullptr ? map_private(*other.base_) : nullptr;
  if (mapped == nullptr) {
    // Never shared, or the system refuses another mapping (vm.max_map_count): a plain copy, the
    // same bytes at the cost of the memory.
    data_ = static_cast<std::byte*>(std::malloc(size_));
    if (data_ == nullptr) throw std::bad_alloc();
    std::memcpy(data_, other.data_, size_);
    return;
  }
  base_ = other.base_;
  data_ = mapped;
  written_ = std::move(written);
  pristine_ = true;
  if (other.pristine_) return;
  // Only the pages `other` changed are written here (and so copied by the kernel).
  const std::size_t page = page_size();
  for (std::size_t at = 0; at < size_; at += page) {
    const std::size_t n = std::min(page, size_ - at);
    if (std::memcmp(other.data_ + at, base_->view + at, n) == 0) continue;
    std::memcpy(data_ + at, other.data_ + at, n);
    note_written(at);
  }
}

SharedPages& SharedPages::operator=(const SharedPages& other) {
  if (this != &other) *this = SharedPages(other);
  return *this;
}

SharedPages::SharedPages(SharedPages&& other) noexcept
    : base_(std::move(other.base_)), data_(std::exchange(other.data_, nullptr)), size_(std::exchange(other.size_, 0)),
      pristine_(std::exchange(other.pristine_, false)), written_(std::move(other.written_)),
      written_all_(std::exchange(other.written_all_, false)) {}

SharedPages& SharedPages::operator=(SharedPages&& other) noexcept {
  if (this != &other) {
    release();
    base_ = std::move(other.base_);
    data_ = std::exchange(other.data_, nullptr);
    size_ = std::exchange(other.size_, 0);
    pristine_ = std::exchange(other.pristine_, false);
    written_ = std::move(other.written_);
    written_all_ = std::exchange(other.written_all_, false);
  }
  return *this;
}

SharedPages::~SharedPages() { release(); }

void SharedPages::release() noexcept {
  if (data_ != nullptr) {
    if (base_ != nullptr) {
      unmap_counted(data_, size_);
    } else {
      std::free(data_);
    }
  }
  data_ = nullptr;
  base_.reset();
  written_.clear();
  written_all_ = false;
}

void SharedPages::share() {
  if (size_ < kMinShared || (base_ != nullptr && pristine_)) return;
  auto file = std::make_shared<File>();
  file->size = size_;
  file->fd = memfd_create("vwg-shared-pages", MFD_CLOEXEC);
  if (file->fd < 0 || ftruncate(file->fd, static_cast<off_t>(size_)) != 0) return;  // stays a plain buffer
  std::byte* view = map_counted(file->fd, size_, PROT_READ | PROT_WRITE, MAP_SHARED);
  if (view == nullptr) return;  // stays a plain buffer
  file->view = view;            // unmapped with the file from here on
  std::memcpy(view, data_, size_);
  if (mprotect(view, round_up(size_), PROT_READ) != 0) return;
  std::vector<std::uint64_t> written((size_ + page_size() - 1) / page_size() / 64 + 1, 0);
  std::byte* mapped = map_private(*file);
  if (mapped == nullptr) return;  // stays a plain buffer
  const std::size_t size = size_;
  release();
  size_ = size;
  data_ = mapped;
  base_ = std::move(file);
  pristine_ = true;
  written_ = std::move(written);
}

std::span<const std::byte> SharedPages::original() const {
  if (base_ == nullptr) return {};
  return {base_->view, size_};
}

std::size_t SharedPages::private_pages() const {
  if (base_ == nullptr || pristine_) return 0;
  const std::size_t page = page_size();
  std::size_t n = 0;
  for (std::size_t at = 0; at < size_; at += page) {
    n += std::memcmp(data_ + at, base_->view + at, std::min(page, size_ - at)) != 0;
  }
  return n;
}

std::size_t SharedPages::reshare() {
  if (base_ == nullptr) return 0;
  constexpr std::size_t kNone = ~std::size_t{0};
  const std::size_t page = page_size(), pages = (size_ + page - 1) / page;
  std::size_t given = 0, run = kNone;  // run: the first of the pages found equal, not yet given back
  const auto give_back = [&](std::size_t end) {
    // Dropping private pages of a private file mapping brings back the file's pages (equal here);
    // for a page that was not private it only drops the page table entry.
    if (run != kNone && madvise(data_ + run * page, (end - run) * page, MADV_DONTNEED) == 0) given += end - run;
    run = kNone;
  };
  bool differs = false;
  for (std::size_t p = 0; p < pages; ++p) {
    if (!written_all_ && ((written_[p / 64] >> (p % 64)) & 1) == 0) {
      give_back(p);
      if (written_[p / 64] == 0) p |= 63;  // a word of pages not written: skip it
      continue;
    }
    const std::size_t at = p * page;
    if (std::memcmp(data_ + at, base_->view + at, std::min(page, size_ - at)) != 0) {
      give_back(p);
      differs = true;
    } else if (run == kNone) {
      run = p;
    }
  }
  give_back(pages);
  if (written_all_ && !differs) pristine_ = true;
  std::fill(written_.begin(), written_.end(), 0);
  written_all_ = false;
  return given;
}

}  // namespace vwg
