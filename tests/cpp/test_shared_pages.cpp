// Buffers whose copies share the pages they do not write (SharedPages), checked against what the
// kernel reports of each mapping (/proc/self/smaps: a page copied on write is an anonymous page).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "helpers.hpp"
#include "vwg/blob.hpp"
#include "vwg/log.hpp"
#include "vwg/detail/shared_pages.hpp"

using namespace vwg;

namespace {

std::size_t anonymous_bytes(const void* start) {
  const long long n = vwg::testing::anonymous_bytes(start);
  EXPECT_GE(n, 0) << "no mapping starts at " << start;
  return static_cast<std::size_t>(std::max(n, 0LL));
}

SharedPages pattern(std::size_t size) {
  SharedPages b(size);
  for (std::size_t i = 0; i < size; ++i) b.data()[i] = static_cast<std::byte>(i * 7 + 3);
  return b;
}

bool same(const SharedPages& a, const SharedPages& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size()) == 0;
}

std::uint64_t read_all(const SharedPages& b) {
  std::uint64_t sum = 0;
  for (std::size_t i = 0; i < b.size(); i += 512) sum += static_cast<std::uint64_t>(b.data()[i]);
  return sum;
}

}  // namespace

TEST(SharedPages, CopiesOfASharedBufferCopyOnlyThePagesTheyWrite) {
  const std::size_t page = SharedPages::page_size(), size = 256 * page + 100;  // a partial last page
  SharedPages original = pattern(size);
  const SharedPages plain = original;  // before share(): a plain copy
  original.share();
  ASSERT_TRUE(original.shared());
  ASSERT_TRUE(same(original, plain));
  SharedPages copy = original;
  ASSERT_TRUE(same(copy, plain));
  read_all(copy);
  EXPECT_EQ(anonymous_bytes(std::as_const(copy).data()), 0u) << "read, never written: every page the file's";
  copy.data()[5 * page + 1] = std::byte{0};
  copy.data()[5 * page + 2] = std::byte{0};
  copy.data()[size - 1] = std::byte{0};
  EXPECT_EQ(anonymous_bytes(std::as_const(copy).data()), 2 * page) << "two pages written, two copied";
  EXPECT_EQ(copy.private_pages(), 2u);
  EXPECT_TRUE(same(original, plain)) << "the original does not see its copy's writes";
  EXPECT_EQ(original.private_pages(), 0u);
  original.data()[0] = std::byte{42};
  EXPECT_EQ(copy.data()[0], plain.data()[0]) << "nor the copy its original's";
}

TEST(SharedPages, ACopyOfAWrittenBufferHasItsBytesAndSharesTheRest) {
  const std::size_t page = SharedPages::page_size(), size = 64 * page;
  SharedPages first = pattern(size);
  first.share();
  SharedPages second = first;
  for (std::size_t p : {3u, 17u, 63u}) second.data()[p * page + 9] = std::byte{1};
  const SharedPages third = second;  // compares second with the file page by page
  EXPECT_TRUE(same(third, second));
  EXPECT_EQ(third.private_pages(), 3u);
  read_all(third);
  EXPECT_EQ(anonymous_bytes(third.data()), 3 * page);
}

TEST(SharedPages, ReshareGivesBackThePagesWrittenThatAreEqualAgain) {
  const std::size_t page = SharedPages::page_size(), size = 32 * page;
  SharedArray<std::uint8_t> original(size);
  for (std::size_t i = 0; i < size; ++i) original.set(i, static_cast<std::uint8_t>(i * 7 + 3));
  original.share();
  SharedArray<std::uint8_t> copy = original;
  const std::uint8_t was = copy[4 * page], other = copy[9 * page];
  copy.set(4 * page, static_cast<std::uint8_t>(~was));
  copy.set(9 * page, static_cast<std::uint8_t>(~other));
  copy.set(4 * page, was);  // seen, then gone: equal to the shared content again
  ASSERT_EQ(anonymous_bytes(std::as_const(copy).data()), 2 * page);
  EXPECT_EQ(copy.reshare(), 1u) << "page 4 given back; page 9 still differs";
  EXPECT_EQ(anonymous_bytes(std::as_const(copy).data()), page);
  EXPECT_EQ(copy[4 * page], was);
  EXPECT_EQ(copy.reshare(), 0u) << "nothing written since";
  copy.set(9 * page, other);
  EXPECT_EQ(copy.reshare(), 1u);
  std::uint64_t sum = 0;
  for (std::size_t i = 0; i < size; i += 512) sum += copy[i];
  EXPECT_GT(sum, 0u);
  EXPECT_EQ(anonymous_bytes(std::as_const(copy).data()), 0u);
  EXPECT_EQ(std::memcmp(copy.data(), original.data(), size), 0);
  EXPECT_EQ(copy.private_pages(), 0u);
}

TEST(SharedPages, SmallBuffersAreCopiedAndMovesTakeTheMapping) {
  SharedPages small = pattern(1000);
  small.share();
  EXPECT_FALSE(small.shared()) << "below kMinShared";
  SharedPages small_copy = small;
  small_copy.data()[0] = std::byte{9};
  EXPECT_NE(small.data()[0], std::byte{9});

  SharedPages big = pattern(SharedPages::kMinShared);
  big.share();
  const std::byte* at = big.data();
  SharedPages moved = std::move(big);
  EXPECT_EQ(moved.data(), at);
  EXPECT_TRUE(moved.shared());
  EXPECT_EQ(big.size(), 0u);  // NOLINT(bugprone-use-after-move): a moved-from buffer is empty
  SharedPages assigned;
  assigned = moved;
  EXPECT_TRUE(same(assigned, moved));
  EXPECT_NE(assigned.data(), moved.data());
}

TEST(SharedPages, ABlobCopyKeepsContentRevisionAndHash) {
  Blob map(DType::Int16, {300, 400});
  auto cells = map.mutable_view<std::int16_t>();
  for (std::size_t i = 0; i < cells.size(); ++i) cells[i] = static_cast<std::int16_t>(i % 1000 - 1);
  const std::uint64_t hash = map.content_hash();
  map.share();
  EXPECT_TRUE(map.shared());
  EXPECT_EQ(map.content_hash(), hash) << "sharing changes no byte";
  auto copy = map.clone();
  EXPECT_TRUE(copy->same_content(map));
  EXPECT_EQ(copy->revision(), map.revision());
  EXPECT_EQ(copy->private_pages(), 0u);
  copy->mutable_view<std::int16_t>()[77] = 5;
  EXPECT_FALSE(copy->same_content(map));
  EXPECT_EQ(copy->private_pages(), 1u);
  EXPECT_EQ(map.view<std::int16_t>()[77], 76);
}

TEST(SharedPages, CopiesPastTheMappingBudgetArePlainCopiesAndTheLogSaysWhy) {
  // Each shared copy is a memory mapping, and Linux allows vm.max_map_count of them per process
  // (65,530 by default). Past vwg's budget (set small here), copies must still hold the content,
  // as plain copies; the log must say once why memory now goes faster; mappings given back make
  // room again.
  std::string said;
  int warnings = 0;
  set_log_sink([&](LogLevel level, std::string_view source, std::string_view message) {
    if (level == LogLevel::Warning && source == "shared_pages") ++warnings, said = message;
  });
  const std::size_t budget = SharedPages::mapping_budget();
  struct Restore {  // the budget and the sink, however the test ends
    std::size_t budget;
    ~Restore() {
      SharedPages::set_mapping_budget(budget);
      set_log_sink({});
    }
  } restore{budget};
  EXPECT_GE(budget, 4096u) << "all but 4,096 of vm.max_map_count (half of a small one)";
  SharedPages original(SharedPages::kMinShared);
  original.data()[100] = std::byte{7};
  original.share();
  ASSERT_TRUE(original.shared());
  const std::size_t before = SharedPages::mappings();
  {
    const SharedPages copy(original);
    EXPECT_EQ(SharedPages::mappings(), before + 1) << "a copy is one mapping";
  }
  EXPECT_EQ(SharedPages::mappings(), before) << "and gives it back";
  SharedPages::set_mapping_budget(before + 3);
  std::vector<SharedPages> copies(5, original);
  for (std::size_t k = 0; k < copies.size(); ++k) {
    EXPECT_EQ(copies[k].shared(), k < 3) << k;
    EXPECT_EQ(std::as_const(copies[k]).data()[100], std::byte{7}) << k;
  }
  EXPECT_EQ(SharedPages::mappings(), before + 3);
  SharedPages plain(SharedPages::kMinShared);
  plain.share();
  EXPECT_FALSE(plain.shared()) << "share() too stays within the budget";
  EXPECT_EQ(warnings, 1) << "said once";
  EXPECT_NE(said.find("vm.max_map_count"), std::string::npos) << said;
  copies.erase(copies.begin());  // a shared copy goes: room for one more
  copies.push_back(original);
  EXPECT_TRUE(copies.back().shared());
  copies.clear();
  EXPECT_EQ(SharedPages::mappings(), before);
}
