// A blob's log of element writes (Blob::written_since), against the elements that differ from a
// copy taken at the mark.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <set>
#include <vector>

#include "vwg/blob_edit.hpp"

using namespace vwg;

TEST(Blob, WrittenSinceNamesEveryElementWrittenSinceAMark) {
  // Against a second method: the elements that differ between a copy taken at the mark and the
  // blob now must all be named, and nothing may be named that was not written.
  std::mt19937 rng(21);
  Blob blob(DType::Int16, {50, 40});
  std::vector<std::int16_t> at_mark(blob.size(), 0);
  Blob::Mark mark = blob.mark();
  std::set<std::size_t> written;
  BlobEdit<std::int16_t> edit(blob);
  for (int step = 0; step < 200; ++step) {
    const int writes = static_cast<int>(rng() % 30);
    for (int k = 0; k < writes; ++k) {
      const std::size_t i = rng() % blob.size();
      const auto v = static_cast<std::int16_t>(rng() % 3);
      if (edit[i] != v) written.insert(i);
      edit.set(i, v);
    }
    std::set<std::size_t> named;
    ASSERT_TRUE(blob.written_since(mark, [&](std::size_t i) { named.insert(i); })) << step;
    EXPECT_EQ(named, written) << step;
    const auto now = blob.view<std::int16_t>();
    for (std::size_t i = 0; i < now.size(); ++i) {
      if (now[i] != at_mark[i]) {
        ASSERT_TRUE(named.count(i)) << "step " << step << ": element " << i << " changed unnamed";
      }
    }
    if (rng() % 3 == 0) {  // a new mark
      mark = blob.mark();
      at_mark.assign(now.begin(), now.end());
      written.clear();
    }
  }
}

TEST(Blob, WrittenSinceSaysWhenItCannotTell) {
  Blob blob(DType::Int16, {100, 100});
  BlobEdit<std::int16_t> edit(blob);
  edit.set(7, 1);
  const Blob::Mark mark = blob.mark();
  int named = 0;
  EXPECT_TRUE(blob.written_since(mark, [&](std::size_t) { ++named; }));
  EXPECT_EQ(named, 0) << "nothing written since";
  // A copy made after the mark follows on from it; a write to the original after the copy does
  // not belong to the copy's history.
  edit.set(8, 1);
  const auto copy = blob.clone();
  std::vector<std::size_t> in_copy;
  EXPECT_TRUE(copy->written_since(mark, [&](std::size_t i) { in_copy.push_back(i); }));
  EXPECT_EQ(in_copy, std::vector<std::size_t>{8});
  edit.set(9, 1);
  BlobEdit<std::int16_t>(*copy).set(10, 1);
  const Blob::Mark copy_mark = copy->mark();  // a content the original never had
  EXPECT_FALSE(blob.written_since(copy_mark, [&](std::size_t) { ++named; })) << "a mark of another history";
  // The original written whole right after the copy: a mark of it then is not of the copy's history.
  {
    Blob original(DType::Int16, {10, 10});
    BlobEdit<std::int16_t>(original).set(1, 1);
    const auto forked = original.clone();
    original.mutable_view<std::int16_t>()[2] = 2;
    EXPECT_FALSE(forked->written_since(original.mark(), [&](std::size_t) { ++named; }));
  }
  // More writes than the log keeps.
  for (std::size_t k = 0; k < Blob::kLoggedWrites; ++k) edit.set(k, static_cast<std::int16_t>(edit[k] + 1));
  EXPECT_FALSE(blob.written_since(mark, [&](std::size_t) { ++named; }));
  // A write of the whole blob: nothing before it can be told, and the log starts again after it.
  const Blob::Mark before_whole = blob.mark();
  blob.mutable_view<std::int16_t>()[3] = 5;
  EXPECT_FALSE(blob.written_since(before_whole, [&](std::size_t) { ++named; }));
  EXPECT_EQ(named, 0) << "nothing named when it cannot tell";
  const Blob::Mark after_whole = blob.mark();
  edit.set(4, 6);
  std::vector<std::size_t> after;
  EXPECT_TRUE(blob.written_since(after_whole, [&](std::size_t i) { after.push_back(i); }));
  EXPECT_EQ(after, std::vector<std::size_t>{4});
}
