#include "vwg/plan/movingai.hpp"

#include <algorithm>
#include <charconv>
#include <fstream>
#include <sstream>

#include "vwg/error.hpp"

namespace vwg::plan {

namespace {

/// Lines of a text file without their line ends, LF or CRLF.
std::vector<std::string> read_lines(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open " + path.string());
  std::vector<std::string> lines;
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    lines.push_back(std::move(line));
  }
  return lines;
}

[[noreturn]] void fail(const std::filesystem::path& path, std::size_t line, std::size_t column, std::string found,
                       std::string expected, std::string text) {
  throw ParseError(path.string(), line, column, std::move(found), std::move(expected), std::move(text));
}

/// The integer after `key ` on a header line such as "height 49".
int header_value(const std::filesystem::path& path, const std::vector<std::string>& lines, std::size_t i,
                 const std::string& key) {
  const std::string& line = i < lines.size() ? lines[i] : std::string();
  int value = 0;
  const char* first = line.data() + std::min(line.size(), key.size() + 1);
  const auto [end, ec] = std::from_chars(first, line.data() + line.size(), value);
  if (line.rfind(key + " ", 0) != 0 || ec != std::errc() || end != line.data() + line.size() || value < 0) {
    fail(path, i + 1, 1, "'" + line + "'", "'" + key + " <non-negative integer>'", line);
  }
  return value;
}

}  // namespace

MovingAiMap read_movingai_map(const std::filesystem::path& path) {
  const std::vector<std::string> lines = read_lines(path);
  if (lines.empty() || lines[0].rfind("type ", 0) != 0) {
    fail(path, 1, 1, lines.empty() ? "an empty file" : "'" + lines[0] + "'", "'type octile'",
         lines.empty() ? "" : lines[0]);
  }
  MovingAiMap map;
  map.height = header_value(path, lines, 1, "height");
  map.width = header_value(path, lines, 2, "width");
  if (lines.size() < 4 || lines[3] != "map") {
    fail(path, 4, 1, lines.size() < 4 ? "the end of the file" : "'" + lines[3] + "'", "'map'",
         lines.size() < 4 ? "" : lines[3]);
  }
  if (lines.size() < 4 + static_cast<std::size_t>(map.height)) {
    fail(path, lines.size() + 1, 1, "the end of the file", std::to_string(map.height) + " map rows", "");
  }
  map.grid = BlockedGrid(map.height, map.width);
  for (int r = 0; r < map.height; ++r) {
    const std::string& row = lines[4 + static_cast<std::size_t>(r)];
    if (row.size() != static_cast<std::size_t>(map.width)) {
      fail(path, 5 + static_cast<std::size_t>(r), std::min(row.size(), static_cast<std::size_t>(map.width)) + 1,
           "a row of " + std::to_string(row.size()) + " characters", std::to_string(map.width) + " characters", row);
    }
    for (int c = 0; c < map.width; ++c) {
      const char ch = row[static_cast<std::size_t>(c)];
      map.grid.set_blocked({r, c}, !(ch == '.' || ch == 'G' || ch == 'S'));
    }
  }
  return map;
}

std::vector<MovingAiScenario> read_movingai_scenarios(const std::filesystem::path& path) {
  const std::vector<std::string> lines = read_lines(path);
  if (lines.empty() || lines[0].rfind("version", 0) != 0) {
    fail(path, 1, 1, lines.empty() ? "an empty file" : "'" + lines[0] + "'", "'version 1'",
         lines.empty() ? "" : lines[0]);
  }
  std::vector<MovingAiScenario> out;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    if (lines[i].find_first_not_of(" \t") == std::string::npos) continue;
    std::istringstream fields(lines[i]);
    MovingAiScenario s;
    int sx = 0, sy = 0, gx = 0, gy = 0;
    if (!(fields >> s.bucket >> s.map >> s.map_width >> s.map_height >> sx >> sy >> gx >> gy >> s.optimal_length)) {
      fail(path, i + 1, 1, "'" + lines[i] + "'",
           "bucket, map, width, height, start x, start y, goal x, goal y, optimal length", lines[i]);
    }
    s.start = {sy, sx};
    s.goal = {gy, gx};
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace vwg::plan
