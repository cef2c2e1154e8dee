#include "vwg/plan/movingai.hpp"

#include <algorithm>
#include <charconv>
#include <climits>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <sstream>

#include "vwg/error.hpp"

namespace vwg::plan {

namespace {

/// The text of a file, refused unread when it is not a regular file (a named pipe would block).
std::string read_file(const std::filesystem::path& path) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status)) throw FileError(path.string(), "", "file not found");
  if (!std::filesystem::is_regular_file(status)) throw FileError(path.string(), "", "expected a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(path.string(), "", "cannot read the file");
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Lines without their ends (LF, CRLF or a lone CR); a text ending in a line end has an empty last line.
std::vector<std::string_view> split_lines(std::string_view text) {
  std::vector<std::string_view> lines;
  std::size_t start = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\n' || text[i] == '\r') {
      lines.push_back(text.substr(start, i - start));
      if (text[i] == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
      start = i + 1;
    }
  }
  lines.push_back(text.substr(start));
  return lines;
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\v' || c == '\f'; }

std::string_view strip(std::string_view s) {
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> words(std::string_view s) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && is_space(s[i])) ++i;
    const std::size_t start = i;
    while (i < s.size() && !is_space(s[i])) ++i;
    if (i > start) out.push_back(s.substr(start, i - start));
  }
  return out;
}

/// Text in quotes for a message; bytes that do not print as \xNN.
std::string quoted(std::string_view s) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out = "'";
  for (const char ch : s) {
    const auto b = static_cast<unsigned char>(ch);
    if (b >= 0x20 && b < 0x7f && ch != '\'' && ch != '\\') {
      out += ch;
    } else if (ch == '\'' || ch == '\\') {
      out += '\\';
      out += ch;
    } else {
      out += "\\x";
      out += kHex[b >> 4];
      out += kHex[b & 15];
    }
  }
  return out + "'";
}

/// "height 49" → the value's text; FileError(key) when the line is missing, blank or not `key <value>`.
std::string_view header(const std::string& source, const std::vector<std::string_view>& lines, std::size_t i,
                        const std::string& key) {
  const std::size_t line = i + 1;
  if (i >= lines.size() || strip(lines[i]).empty()) {
    throw FileError(source, key, "expected '" + key + " ...' on line " + std::to_string(line), line, 1);
  }
  const auto parts = words(lines[i]);
  if (parts[0] != key || parts.size() != 2) {
    throw FileError(source, key, "expected '" + key + " <value>', got " + quoted(strip(lines[i])), line, 1);
  }
  return parts[1];
}

/// A whole number > 0 of at most 18 digits (more is refused by the size check, which needs its text only).
struct Dimension {
  std::string_view text;
  std::uint64_t value = 0;  ///< UINT64_MAX when it has more digits than that holds
};

Dimension dimension(const std::string& source, std::string_view text, std::size_t line, const std::string& key) {
  const bool digits = !text.empty() && std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
  if (!digits || text.find_first_not_of('0') == std::string_view::npos) {
    throw FileError(source, key, "expected a whole number > 0, got " + quoted(text), line, 1);
  }
  Dimension d{text, UINT64_MAX};
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), d.value);
  if (ec != std::errc() || end != text.data() + text.size()) d.value = UINT64_MAX;
  return d;
}

const char* terrain_help() { return "(passable: . G S; blocked: @ O T W)"; }

/// -1 for a character the format does not have, else whether the terrain blocks.
int blocks(char c) {
  switch (c) {
    case '.': case 'G': case 'S': return 0;
    case '@': case 'O': case 'T': case 'W': return 1;
    default: return -1;
  }
}

}  // namespace

MovingAiMap parse_movingai_map(std::string_view text, const std::string& source) {
  // The format is ASCII: a byte above 127 is a file of another kind (or a damaged one).
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto b = static_cast<unsigned char>(text[i]);
    if (b >= 0x80) {
      static constexpr char kHex[] = "0123456789abcdef";
      const auto before = split_lines(text.substr(0, i));
      throw FileError(source, "map", std::string("not an ASCII MovingAI map (byte 0x") + kHex[b >> 4] + kHex[b & 15] + ")",
                      before.size(), before.back().size() + 1);
    }
  }
  std::vector<std::string_view> lines = split_lines(text);
  header(source, lines, 0, "type");
  const Dimension h = dimension(source, header(source, lines, 1, "height"), 2, "height");
  const Dimension w = dimension(source, header(source, lines, 2, "width"), 3, "width");
  if (lines.size() < 4 || strip(lines[3]) != "map") {
    throw FileError(source, "map", "expected 'map' on line 4, got " + (lines.size() > 3 ? quoted(strip(lines[3])) : "'end of file'"),
                    4, 1);
  }
  // Checked before the grid is made: the header may claim more cells than the file has bytes.
  const std::uint64_t size = text.size();
  if (w.value > size || h.value > size / w.value || h.value > INT_MAX || w.value > INT_MAX) {
    throw FileError(source, "width", "the header says " + std::string(h.text) + " rows of " + std::string(w.text) +
                                         " cells, more than the file's " + std::to_string(size) + " bytes hold", 3, 1);
  }
  while (lines.size() > 4 && strip(lines.back()).empty()) lines.pop_back();  // blank lines end the file
  MovingAiMap map;
  map.height = static_cast<int>(h.value);
  map.width = static_cast<int>(w.value);
  const std::size_t rows = lines.size() - 4;
  const auto height = static_cast<std::size_t>(map.height), width = static_cast<std::size_t>(map.width);
  if (rows < height) {
    throw FileError(source, "map", "expected " + std::to_string(height) + " rows (the header says height " +
                                       std::to_string(height) + "), got " + std::to_string(rows), 4 + rows + 1);
  }
  if (rows > height) {
    throw FileError(source, "map", "more than " + std::to_string(height) + " rows (the header says height " +
                                       std::to_string(height) + ")", 4 + height + 1);
  }
  map.grid = BlockedGrid(map.height, map.width);
  for (std::size_t r = 0; r < height; ++r) {
    const std::string_view row = lines[4 + r];
    const std::string field = "map[" + std::to_string(r) + "]";
    if (row.size() != width) {
      throw FileError(source, field, "row has " + std::to_string(row.size()) + " characters, expected " + std::to_string(width),
                      5 + r, std::min(row.size(), width) + 1);
    }
    for (std::size_t c = 0; c < width; ++c) {
      const int b = blocks(row[c]);
      if (b < 0) {
        throw FileError(source, field, "unknown terrain " + quoted(row.substr(c, 1)) + " at column " + std::to_string(c + 1) +
                                           " " + terrain_help(), 5 + r, c + 1);
      }
      if (b) map.grid.set_blocked({static_cast<int>(r), static_cast<int>(c)}, true);
    }
  }
  return map;
}

MovingAiMap read_movingai_map(const std::filesystem::path& path) { return parse_movingai_map(read_file(path), path.string()); }

std::vector<MovingAiScenario> parse_movingai_scenarios(std::string_view text, const std::string& source) {
  std::vector<std::string_view> lines = split_lines(text);
  if (lines.empty() || words(lines[0]).empty() || words(lines[0])[0] != "version") {
    throw FileError(source, "version", "expected 'version 1' on line 1, got " + quoted(strip(lines[0])), 1, 1);
  }
  std::vector<MovingAiScenario> out;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    if (strip(lines[i]).empty()) continue;
    std::istringstream fields{std::string(lines[i])};
    MovingAiScenario s;
    int sx = 0, sy = 0, gx = 0, gy = 0;
    std::string rest;
    if (!(fields >> s.bucket >> s.map >> s.map_width >> s.map_height >> sx >> sy >> gx >> gy >> s.optimal_length) ||
        (fields >> rest)) {
      throw FileError(source, "scenario",
                      "expected bucket, map, width, height, start x, start y, goal x, goal y, optimal length; got " +
                          quoted(strip(lines[i])), i + 1, 1);
    }
    s.start = {sy, sx};
    s.goal = {gy, gx};
    out.push_back(std::move(s));
  }
  return out;
}

std::vector<MovingAiScenario> read_movingai_scenarios(const std::filesystem::path& path) {
  return parse_movingai_scenarios(read_file(path), path.string());
}

geometry::OccupancyGrid to_occupancy_grid(const MovingAiMap& map, double resolution, const geometry::Pose2& origin) {
  geometry::OccupancyGrid g;
  g.width = map.width;
  g.height = map.height;
  g.resolution = resolution;
  g.origin = origin;
  g.data.resize(static_cast<std::size_t>(map.width) * static_cast<std::size_t>(map.height));
  for (int r = 0; r < map.height; ++r) {
    std::int8_t* row = g.data.data() + static_cast<std::size_t>(map.height - 1 - r) * static_cast<std::size_t>(map.width);
    for (int c = 0; c < map.width; ++c) row[c] = map.grid.blocked({r, c}) ? geometry::kOccupied : geometry::kFree;
  }
  return g;
}

}  // namespace vwg::plan
