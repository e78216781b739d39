#include "slice/surface.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <string_view>
#include <utility>

#include "slice/error.hpp"
#include "slice/utf8.hpp"
#include "slice/vertices.hpp"

namespace slice {
namespace {

constexpr const char* kGridFix =
    "give an ESRI ASCII grid: header lines ncols, nrows, xllcorner (or xllcenter), yllcorner "
    "(or yllcenter), cellsize and optionally NODATA_value, then nrows rows of ncols heights, "
    "the north row first";
constexpr const char* kHeightFieldFix =
    "give a height field z = h(x, y) (no overhang, no vertical face), or give the rock above as "
    "a closed solid with mesh = \"...\"";

std::string num(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}
std::string point(double x, double y) { return "(" + num(x) + ", " + num(y) + ")"; }
std::string range(double lo, double hi) { return "[" + num(lo) + ", " + num(hi) + "]"; }

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::string at_line(const std::filesystem::path& file, std::int64_t line) {
  return file.string() + ":" + std::to_string(line);
}

// At most 40 characters of a token for a message, quoted; bytes that are no UTF-8 escaped
// (\xe9), "..." where it is cut: a message never echoes a whole file.
std::string shown(std::string_view s) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out = "\"";
  std::size_t i = 0;
  for (std::size_t n = 0; i < s.size() && n < 40; ++n) {
    const auto [c, len] = decode_utf8(s, i);
    if (len == 0 || c < 0x20 || c == 0x7f) {
      const auto u = static_cast<unsigned char>(s[i++]);
      out += "\\x";
      out += kHex[u >> 4];
      out += kHex[u & 15];
    } else {
      out.append(s.substr(i, len));
      i += len;
    }
  }
  return out + (i < s.size() ? "...\"" : "\"");
}

// The whitespace-separated tokens of a text, with the line of each. A line ends at LF, CRLF or
// a lone CR (old Mac files).
struct Tokens {
  std::string_view text;
  std::size_t pos = 0;
  std::int64_t line = 1;  // the line of the last token next() returned
  std::string_view next() {
    while (pos < text.size() && std::isspace(static_cast<unsigned char>(text[pos]))) {
      if (text[pos] == '\n' ||
          (text[pos] == '\r' && (pos + 1 == text.size() || text[pos + 1] != '\n')))
        ++line;
      ++pos;
    }
    const std::size_t start = pos;
    while (pos < text.size() && !std::isspace(static_cast<unsigned char>(text[pos]))) ++pos;
    return text.substr(start, pos - start);
  }
};

bool to_double(std::string_view s, double& v) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && end == s.data() + s.size();
}

// The header keys of an ESRI ASCII grid (GDAL's AAIGrid driver also reads dx, dy and the
// British "centre").
constexpr std::string_view kGridKeys[] = {"ncols",     "nrows",     "xllcorner", "xllcenter",
                                          "xllcentre", "yllcorner", "yllcenter", "yllcentre",
                                          "cellsize",  "dx",        "dy",        "nodata_value"};

struct HeaderValue {
  std::string text;
  std::int64_t line = 0;
};
using Header = std::map<std::string, HeaderValue>;

double header_number(const std::filesystem::path& file, const Header& h, const std::string& key) {
  const HeaderValue& v = h.at(key);
  double x = 0;
  if (!to_double(v.text, x) || !std::isfinite(x))
    throw Error(at_line(file, v.line), key + " is " + shown(v.text) + ", not a finite number",
                kGridFix);
  return x;
}

std::int64_t header_count(const std::filesystem::path& file, const Header& h,
                          const std::string& key, std::uintmax_t bytes) {
  const HeaderValue& v = h.at(key);
  std::int64_t n = 0;
  const auto [end, ec] = std::from_chars(v.text.data(), v.text.data() + v.text.size(), n);
  if (ec != std::errc() || end != v.text.data() + v.text.size())
    throw Error(at_line(file, v.line), key + " is " + shown(v.text) + ", not a whole number",
                kGridFix);
  if (n < 2)
    throw Error(at_line(file, v.line),
                key + " is " + shown(v.text) +
                    ": heights are at cell centres, and the surface spans between them, so a "
                    "grid needs at least 2 columns and 2 rows",
                kGridFix);
  if (std::uintmax_t(n) > bytes)
    throw Error(at_line(file, v.line),
                key + " is " + shown(v.text) + ", more than the file's " + std::to_string(bytes) +
                    " bytes can hold",
                "the header is damaged or the file is cut off: export the grid again");
  return n;
}

// Exactly one of the keys, or none if `optional`: its name.
std::string one_of(const std::filesystem::path& file, const Header& h,
                   std::initializer_list<std::string> keys, bool optional = false) {
  std::string found;
  for (const std::string& k : keys) {
    if (!h.count(k)) continue;
    if (!found.empty())
      throw Error(at_line(file, h.at(k).line), "the header gives both " + found + " and " + k,
                  "keep one of them");
    found = k;
  }
  if (found.empty() && !optional)
    throw Error(file.string(), "the header has no " + *keys.begin(), kGridFix);
  return found;
}

Header read_header(const std::filesystem::path& file, Tokens& tk) {
  Header h;
  for (;;) {
    const Tokens before = tk;
    const std::string_view key = tk.next();
    std::string k = lower(key);
    // Data starts with a number; "nan" or "inf" is a height (refused as one, below).
    if (key.empty() || !std::isalpha(static_cast<unsigned char>(key[0])) ||
        k.rfind("nan", 0) == 0 || k.rfind("inf", 0) == 0) {
      tk = before;
      return h;
    }
    if (std::find(std::begin(kGridKeys), std::end(kGridKeys), k) == std::end(kGridKeys))
      throw Error(at_line(file, tk.line), "unknown header key " + shown(key), kGridFix);
    if (k == "xllcentre" || k == "yllcentre") k.replace(3, 6, "center");
    if (h.count(k))
      throw Error(at_line(file, tk.line), "the header gives " + k + " twice", "keep one");
    const std::int64_t line = tk.line;
    const std::string_view value = tk.next();
    if (value.empty() || tk.line != line)
      throw Error(at_line(file, line), "header key " + k + " has no value", kGridFix);
    h[k] = {std::string(value), line};
  }
}

}  // namespace

HeightGrid read_ascii_grid(const std::filesystem::path& file) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(file, ec);
  if (ec) throw Error(file.string(), "cannot be read", "check the path");
  if (size > kMaxMeshFileBytes)
    throw Error(file.string(),
                "is " + std::to_string(size >> 20) + " MiB, more than the " +
                    std::to_string(kMaxMeshFileBytes >> 20) + " MiB a surface may have",
                "crop the grid to the domain, or resample it coarser (gdal_translate -projwin, "
                "-tr)");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(file.string(), "cannot be read", "check the path");
  std::ostringstream all;
  all << in.rdbuf();
  const std::string text = all.str();
  if (text.find('\0') != std::string::npos)
    throw Error(file.string(), "is not text (an ESRI ASCII grid is)",
                "give the grid as ESRI ASCII (.asc), e.g. gdal_translate -of AAIGrid");
  Tokens tk{text};
  if (text.rfind("\xEF\xBB\xBF", 0) == 0) tk.pos = 3;  // a UTF-8 byte-order mark: skipped
  const Header h = read_header(file, tk);
  HeightGrid g;
  one_of(file, h, {"ncols"});
  one_of(file, h, {"nrows"});
  g.ncols = header_count(file, h, "ncols", size);
  g.nrows = header_count(file, h, "nrows", size);
  const std::string xk = one_of(file, h, {"xllcorner", "xllcenter"});
  const std::string yk = one_of(file, h, {"yllcorner", "yllcenter"});
  if (one_of(file, h, {"cellsize", "dx"}) == "cellsize") {
    one_of(file, h, {"cellsize", "dy"});
    g.dx = g.dy = header_number(file, h, "cellsize");
  } else {
    one_of(file, h, {"dy"});
    g.dx = header_number(file, h, "dx");
    g.dy = header_number(file, h, "dy");
  }
  if (!(g.dx > 0) || !(g.dy > 0))
    throw Error(at_line(file, h.count("cellsize") ? h.at("cellsize").line : h.at("dx").line),
                "the cell size must be > 0, not " + num(std::min(g.dx, g.dy)), kGridFix);
  g.x0 = header_number(file, h, xk) + (xk == "xllcorner" ? g.dx / 2 : 0);
  g.y0 = header_number(file, h, yk) + (yk == "yllcorner" ? g.dy / 2 : 0);
  if (h.count("nodata_value")) g.nodata = header_number(file, h, "nodata_value");
  // Corner and cell size finite, their sums need not be (xllcorner 1e308, cellsize 1e308).
  if (!std::isfinite(g.x0) || !std::isfinite(g.y0) || !std::isfinite(g.x(g.ncols - 1)) ||
      !std::isfinite(g.y(0)))
    throw Error(at_line(file, h.count("cellsize") ? h.at("cellsize").line : h.at("dx").line),
                "the grid reaches past the largest number (its corner plus " +
                    std::to_string(g.ncols) + " x " + std::to_string(g.nrows) + " cells of " +
                    num(g.dx) + " x " + num(g.dy) + ")",
                "check the header's corner and cell size, and their unit");
  // Each height takes a character and a separator at least: a count the file cannot hold is
  // refused before memory is taken for it.
  const std::uintmax_t n = std::uintmax_t(g.ncols) * std::uintmax_t(g.nrows);
  if (n > size / 2 + 1)
    throw Error(at_line(file, h.at("nrows").line),
                "the header claims " + std::to_string(g.nrows) + " x " + std::to_string(g.ncols) +
                    " = " + std::to_string(n) + " heights, more than the file's " +
                    std::to_string(size) + " bytes can hold",
                "the header is damaged or the file is cut off: export the grid again");
  g.z.reserve(std::size_t(n));
  for (std::int64_t row = 0; row < g.nrows; ++row)
    for (std::int64_t col = 0; col < g.ncols; ++col) {
      const std::string_view t = tk.next();
      if (t.empty())
        throw Error(at_line(file, tk.line),
                    "the file ends after " + std::to_string(g.z.size()) + " of the " +
                        std::to_string(g.nrows) + " x " + std::to_string(g.ncols) +
                        " heights the header gives",
                    "the file is cut off, or ncols or nrows is wrong");
      if (col == 0) g.row_line.push_back(tk.line);
      double v = 0;
      if (!to_double(t, v))
        throw Error(at_line(file, tk.line), shown(t) + " is not a number", kGridFix);
      if (!std::isfinite(v))
        throw Error(at_line(file, tk.line), "a height is " + shown(t) + ", not finite",
                    "give missing heights the NODATA_value of the header");
      g.z.push_back(v);
    }
  if (const std::string_view t = tk.next(); !t.empty())
    throw Error(at_line(file, tk.line),
                "more than the " + std::to_string(g.nrows) + " x " + std::to_string(g.ncols) +
                    " heights the header gives (" + shown(t) + ")",
                "ncols or nrows is wrong, or the file holds more than one grid");
  return g;
}

TriangleMesh grid_surface(const HeightGrid& g, const Vec2& lo, const Vec2& hi, double tol,
                          const std::string& where) {
  const double xmin = g.x(0), xmax = g.x(g.ncols - 1), ymin = g.y(g.nrows - 1), ymax = g.y(0);
  if (lo.x() < xmin - tol || hi.x() > xmax + tol || lo.y() < ymin - tol || hi.y() > ymax + tol)
    throw Error(where,
                "the grid's cell centres span x " + range(xmin, xmax) + " and y " +
                    range(ymin, ymax) + ", which do not cover the domain's plan, x " +
                    range(lo.x(), hi.x()) + " and y " + range(lo.y(), hi.y()) +
                    " (heights are at cell centres: the surface ends half a cell inside the "
                    "grid's outer edge)",
                "give a grid that reaches at least half a cell beyond the domain on every side");
  // Cells between centres: column c spans [x(c), x(c + 1)], row r (from the north) spans
  // [y(r + 1), y(r)]. Those that meet the open rectangle (lo, hi).
  std::int64_t c0 = 0, c1 = g.ncols - 2, r0 = 0, r1 = g.nrows - 2;
  while (c0 < c1 && g.x(c0 + 1) <= lo.x()) ++c0;
  while (c1 > c0 && g.x(c1) >= hi.x()) --c1;
  while (r0 < r1 && g.y(r0 + 1) >= hi.y()) ++r0;
  while (r1 > r0 && g.y(r1) <= lo.y()) --r1;
  TriangleMesh m;
  const std::int64_t w = c1 - c0 + 2;  // centres a row
  for (std::int64_t r = r0; r <= r1 + 1; ++r)
    for (std::int64_t c = c0; c <= c1 + 1; ++c) {
      const double z = g.at(r, c);
      if (g.nodata && (z == *g.nodata || (std::isnan(z) && std::isnan(*g.nodata))))
        throw Error(
            g.row_line.empty() ? where : where + ":" + std::to_string(g.row_line[std::size_t(r)]),
            "the height of row " + std::to_string(r + 1) + ", column " + std::to_string(c + 1) +
                " (at " + point(g.x(c), g.y(r)) + ") is the no-data value " + num(z) +
                ", within the domain's plan, x " + range(lo.x(), hi.x()) + " and y " +
                range(lo.y(), hi.y()),
            "fill the grid's gaps (e.g. gdal_fillnodata.py) or shrink the domain to "
            "where the grid has heights");
      m.vertices.emplace_back(g.x(c), g.y(r), z);
    }
  const auto id = [&](std::int64_t r, std::int64_t c) { return (r - r0) * w + (c - c0); };
  for (std::int64_t r = r0; r <= r1; ++r)
    for (std::int64_t c = c0; c <= c1; ++c) {
      // South-west, south-east, north-east, north-west centres; the diagonal SW-NE.
      const std::int64_t sw = id(r + 1, c), se = id(r + 1, c + 1), ne = id(r, c + 1), nw = id(r, c);
      m.triangles.push_back({sw, se, ne});
      m.triangles.push_back({sw, ne, nw});
    }
  return m;
}

TriangleMesh read_surface(const std::filesystem::path& file, const Vec2& lo, const Vec2& hi,
                          double tol) {
  const std::string ext = lower(file.extension().string());
  if (ext == ".asc") return grid_surface(read_ascii_grid(file), lo, hi, tol, file.string());
  if (ext == ".tif" || ext == ".tiff")
    return grid_surface(read_geotiff(file), lo, hi, tol, file.string());
  if (ext != ".obj" && ext != ".stl")
    throw Error(file.string(), "is not .stl, .obj, .asc, .tif or .tiff",
                "give a triangulated surface (STL or OBJ), an ESRI ASCII grid (.asc) or a "
                "GeoTIFF (.tif)");
  try {
    return read_mesh(file);
  } catch (const Error& e) {  // read_mesh's fix speaks of closed meshes
    if (e.fix().rfind("give a closed", 0) != 0) throw;
    throw Error(e.where(), e.problem(),
                "give an open triangulated surface (OBJ: v and f lines; STL: facets)");
  }
}

CroppedSurface crop_surface(const TriangleMesh& surface, const Vec2& lo, const Vec2& hi) {
  const std::size_t n = surface.triangles.size();
  std::vector<char> keep(n, 0);
  std::vector<std::vector<std::size_t>> around(surface.vertices.size());  // triangles of a vertex
  for (std::size_t t = 0; t < n; ++t) {
    Vec2 tlo = Vec2::Constant(INFINITY), thi = -tlo;
    for (const std::int64_t v : surface.triangles[t]) {
      const Vec3& x = surface.vertices[std::size_t(v)];
      tlo = tlo.cwiseMin(Vec2(x.x(), x.y())), thi = thi.cwiseMax(Vec2(x.x(), x.y()));
      around[std::size_t(v)].push_back(t);
    }
    keep[t] = !(tlo.x() > hi.x() || thi.x() < lo.x() || tlo.y() > hi.y() || thi.y() < lo.y());
  }
  // A vertex whose kept triangles are not one fan joined edge to edge (more than one kept run
  // about it: more than two border edges of the kept part end there) takes all its triangles
  // back; repeated until none is left (triangles are only added, so it ends).
  for (bool again = true; again;) {
    again = false;
    for (std::size_t v = 0; v < around.size(); ++v) {
      std::map<std::int64_t, int> edge_uses;  // the other end of each kept edge at v
      bool any = false, all = true;
      for (const std::size_t t : around[v]) {
        all = all && keep[t];
        if (!keep[t]) continue;
        any = true;
        for (const std::int64_t w : surface.triangles[t])
          if (std::size_t(w) != v) ++edge_uses[w];
      }
      if (!any || all) continue;
      int border = 0;
      for (const auto& [w, uses] : edge_uses) border += uses == 1 ? 1 : 0;
      if (border <= 2) continue;
      for (const std::size_t t : around[v]) keep[t] = 1;
      again = true;
    }
  }
  // The vertices kept in their order, so that a surface kept whole is the same mesh.
  CroppedSurface c;
  std::vector<std::int64_t> index(surface.vertices.size(), -1);
  for (std::size_t t = 0; t < n; ++t)
    if (keep[t])
      for (const std::int64_t v : surface.triangles[t]) index[std::size_t(v)] = 0;
  for (std::size_t v = 0; v < index.size(); ++v)
    if (index[v] == 0) {
      index[v] = std::int64_t(c.mesh.vertices.size());
      c.mesh.vertices.push_back(surface.vertices[v]);
    }
  for (std::size_t t = 0; t < n; ++t) {
    if (!keep[t]) continue;
    const auto& tri = surface.triangles[t];
    c.mesh.triangles.push_back(
        {index[std::size_t(tri[0])], index[std::size_t(tri[1])], index[std::size_t(tri[2])]});
    c.numbers.push_back(std::int64_t(t + 1));
  }
  return c;
}

std::vector<Vec2> plan_hull(std::span<const Vec3> points) {
  std::vector<Vec2> p;
  for (const Vec3& x : points) p.emplace_back(x.x(), x.y());
  std::sort(p.begin(), p.end(), [](const Vec2& a, const Vec2& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  p.erase(std::unique(p.begin(), p.end()), p.end());
  if (p.size() < 3) return p;
  const auto cross = [](const Vec2& o, const Vec2& a, const Vec2& b) {
    return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
  };
  // Andrew's monotone chain: the lower hull left to right, then the upper right to left.
  std::vector<Vec2> h(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  h.resize(k - 1);
  return h;
}

namespace {

Vec3 flat(const Vec3& x) { return {x.x(), x.y(), 0}; }

// The half-plane left of a -> b in plan (counter-clockwise interiors), as a Plane in z = 0,
// moved inward by `inset`.
Plane inner_side(const Vec2& a, const Vec2& b, double inset = 0) {
  const Vec3 n = Vec3(b.y() - a.y(), a.x() - b.x(), 0).normalized();
  return {n, n.x() * a.x() + n.y() * a.y() - inset};
}

Vec2 xy(const Vec3& x) { return {x.x(), x.y()}; }

// Two triangles (counter-clockwise in plan) whose plan overlap is thicker than tol.
void check_overlaps(const TriangleMesh& s, double tol, const std::string& where,
                    const std::function<std::string(std::size_t)>& number) {
  const std::size_t n = s.triangles.size();
  std::vector<Vec2> lo(n), hi(n);
  Vec2 all_lo = Vec2::Constant(INFINITY), all_hi = -all_lo;
  for (std::size_t t = 0; t < n; ++t) {
    lo[t] = Vec2::Constant(INFINITY), hi[t] = -lo[t];
    for (const std::int64_t v : s.triangles[t]) {
      lo[t] = lo[t].cwiseMin(xy(s.vertices[std::size_t(v)]));
      hi[t] = hi[t].cwiseMax(xy(s.vertices[std::size_t(v)]));
    }
    all_lo = all_lo.cwiseMin(lo[t]), all_hi = all_hi.cwiseMax(hi[t]);
  }
  // Buckets of a k x k grid over the plan: each pair is tested in the bucket of the lower-left
  // corner of their boxes' overlap, once.
  const auto k = std::int64_t(std::ceil(std::sqrt(double(n))));
  const Vec2 cell = ((all_hi - all_lo) / double(k)).cwiseMax(Vec2::Constant(1e-300));
  const auto bucket = [&](const Vec2& x) {
    const auto c = [&](int i) {
      return std::clamp(std::int64_t(std::floor((x(i) - all_lo(i)) / cell(i))), std::int64_t(0),
                        k - 1);
    };
    return std::pair{c(0), c(1)};
  };
  std::vector<std::vector<std::size_t>> buckets(std::size_t(k * k));
  for (std::size_t t = 0; t < n; ++t) {
    const auto [x0, y0] = bucket(lo[t]);
    const auto [x1, y1] = bucket(hi[t]);
    for (std::int64_t y = y0; y <= y1; ++y)
      for (std::int64_t x = x0; x <= x1; ++x) buckets[std::size_t(y * k + x)].push_back(t);
  }
  for (std::size_t b = 0; b < buckets.size(); ++b)
    for (std::size_t p = 0; p < buckets[b].size(); ++p)
      for (std::size_t q = p + 1; q < buckets[b].size(); ++q) {
        const std::size_t i = buckets[b][p], j = buckets[b][q];
        const Vec2 olo = lo[i].cwiseMax(lo[j]), ohi = hi[i].cwiseMin(hi[j]);
        if ((olo.array() > ohi.array()).any()) continue;
        const auto [bx, by] = bucket(olo);
        if (std::size_t(by * k + bx) != b) continue;
        const auto& ti = s.triangles[i];
        const auto& tj = s.triangles[j];
        std::vector<Vec3> part;
        for (const std::int64_t v : ti) part.push_back(flat(s.vertices[std::size_t(v)]));
        for (int e = 0; e < 3 && part.size() >= 3; ++e)
          part = clip_polygon(part, inner_side(xy(s.vertices[std::size_t(tj[std::size_t(e)])]),
                                               xy(s.vertices[std::size_t(tj[(e + 1) % 3])])));
        if (part.size() < 3) continue;
        // Area about the first corner: a point-sized overlap (triangles that share a corner)
        // has none, where shoelace sums of absolute coordinates leave rounding.
        double perimeter = 0, area = 0;
        Vec3 mean = Vec3::Zero();
        for (std::size_t v = 0; v < part.size(); ++v) {
          const Vec3 &p0 = part[v], &p1 = part[(v + 1) % part.size()];
          perimeter += (p1 - p0).norm();
          area += (p0 - part[0]).cross(p1 - part[0]).z() / 2;
          mean += p0 / double(part.size());
        }
        // Thicker than tol: a sliver w wide and L long has area w L and perimeter 2 L.
        if (area > tol * perimeter / 2)
          throw Error(where,
                      "triangles " + number(i) + " and " + number(j) + " overlap in plan near " +
                          point(mean.x(), mean.y()) +
                          ": z is not a function of x and y there (an overhang or a fold)",
                      kHeightFieldFix);
      }
}

// Every edge of the surface's border (a side of one triangle only) stays outside `plan` shrunk
// by tol, and the surface meets the plan's centre: then it covers the plan.
void check_cover(const TriangleMesh& s, std::span<const Vec2> plan, double tol,
                 const std::string& where) {
  std::map<std::pair<std::int64_t, std::int64_t>, std::size_t> edges;  // (lower, higher) -> uses
  for (const auto& t : s.triangles)
    for (int e = 0; e < 3; ++e) {
      const std::int64_t a = t[std::size_t(e)], b = t[std::size_t((e + 1) % 3)];
      ++edges[{std::min(a, b), std::max(a, b)}];
    }
  std::vector<Plane> inner;
  for (std::size_t k = 0; k < plan.size(); ++k)
    inner.push_back(inner_side(plan[k], plan[(k + 1) % plan.size()], tol));
  for (const auto& [e, uses] : edges) {
    if (uses != 1) continue;
    const Vec3 a = flat(s.vertices[std::size_t(e.first)]);
    const Vec3 b = flat(s.vertices[std::size_t(e.second)]);
    double t0 = 0, t1 = 1;  // the part of a + t (b - a) inside every plane
    for (const Plane& h : inner) {
      const double fa = h.distance(a), fb = h.distance(b);
      if (fa > 0 && fb > 0)
        t1 = -1;
      else if (fa > 0)
        t0 = std::max(t0, fa / (fa - fb));
      else if (fb > 0)
        t1 = std::min(t1, fa / (fa - fb));
    }
    if ((t1 - t0) * (b - a).norm() > tol)
      throw Error(where,
                  "the surface does not cover the domain in plan: its border, the edge from " +
                      point(a.x(), a.y()) + " to " + point(b.x(), b.y()) +
                      ", runs inside the domain (a hole, a gap between triangles, triangles "
                      "that do not share whole edges, or a surface too small)",
                  "give a surface that covers the domain in plan, its triangles joined edge "
                  "to edge");
  }
  Vec2 centre = Vec2::Zero();
  for (const Vec2& x : plan) centre += x / double(plan.size());
  const bool met = std::any_of(s.triangles.begin(), s.triangles.end(), [&](const auto& t) {
    for (int e = 0; e < 3; ++e) {
      const Plane h = inner_side(xy(s.vertices[std::size_t(t[std::size_t(e)])]),
                                 xy(s.vertices[std::size_t(t[std::size_t((e + 1) % 3)])]));
      if (h.distance(Vec3(centre.x(), centre.y(), 0)) > tol) return false;
    }
    return true;
  });
  if (!met) {
    Vec3 lo = Vec3::Constant(INFINITY), hi = -lo;
    for (const Vec3& x : s.vertices) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
    throw Error(where,
                "the surface does not cover the domain in plan: it spans x " +
                    range(lo.x(), hi.x()) + " and y " + range(lo.y(), hi.y()) +
                    " and misses the domain's centre " + point(centre.x(), centre.y()),
                "give a surface that covers the domain in plan, in the scene's frame and unit");
  }
}

}  // namespace

TriangleMesh check_height_field(const TriangleMesh& surface, std::span<const Vec2> plan, double tol,
                                const std::string& where, std::span<const std::int64_t> numbers) {
  const auto number = [&](std::size_t t) {
    return std::to_string(t < numbers.size() ? numbers[t] : std::int64_t(t + 1));
  };
  TriangleMesh s = surface;
  Vec3 lo = Vec3::Constant(INFINITY), hi = -lo;
  for (const Vec3& x : s.vertices) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  const double size = (hi - lo).norm();
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {
    auto& tri = s.triangles[t];
    const Vec3 &a = s.vertices[std::size_t(tri[0])], &b = s.vertices[std::size_t(tri[1])],
               &c = s.vertices[std::size_t(tri[2])];
    const Vec3 n = (b - a).cross(c - a);
    const Vec3 mean = (a + b + c) / 3;
    if (n.norm() <= 1e-12 * size * size)
      throw Error(where, "triangle " + number(t) + " has no area",
                  "remove the degenerate triangle");
    if (std::abs(n.z()) <= 1e-9 * n.norm())
      throw Error(where,
                  "triangle " + number(t) + " near " + point(mean.x(), mean.y()) +
                      " is vertical: z is not a function of x and y there",
                  kHeightFieldFix);
    if (n.z() < 0) std::swap(tri[1], tri[2]);  // counter-clockwise seen from above
  }
  check_overlaps(s, tol, where, number);
  check_cover(s, plan, tol, where);
  return s;
}

namespace {

// The border of a surface as one loop a -> b -> ... (each border edge a -> b once), or empty
// if it is not one simple loop (holes, several pieces, corners touched twice).
std::vector<std::int64_t> border_loop(
    const std::vector<std::pair<std::int64_t, std::int64_t>>& border) {
  std::map<std::int64_t, std::int64_t> next;
  for (const auto& [a, b] : border)
    if (!next.emplace(a, b).second) return {};
  std::vector<std::int64_t> loop;
  if (border.empty()) return loop;
  for (std::int64_t v = border.front().first; loop.size() <= border.size();) {
    loop.push_back(v);
    const auto it = next.find(v);
    if (it == next.end()) return {};
    v = it->second;
    if (v == border.front().first) break;
  }
  return loop.size() == border.size() ? loop : std::vector<std::int64_t>{};
}

}  // namespace

TriangleMesh solid_above(const TriangleMesh& up, double top) {
  TriangleMesh m;
  m.vertices = up.vertices;
  std::set<std::pair<std::int64_t, std::int64_t>> directed;
  for (const auto& t : up.triangles) {
    m.triangles.push_back({t[0], t[2], t[1]});  // the surface, facing down
    for (int e = 0; e < 3; ++e) directed.emplace(t[std::size_t(e)], t[std::size_t((e + 1) % 3)]);
  }
  std::map<std::int64_t, std::int64_t> lifted;  // a vertex -> its copy at z = top
  const auto lift = [&](std::int64_t v) {
    const auto [it, fresh] = lifted.emplace(v, std::int64_t(m.vertices.size()));
    if (fresh)
      m.vertices.emplace_back(up.vertices[std::size_t(v)].x(), up.vertices[std::size_t(v)].y(),
                              top);
    return it->second;
  };
  // A wall on each border edge a -> b (no triangle runs b -> a), facing out: right of a -> b.
  std::vector<std::pair<std::int64_t, std::int64_t>> border;
  for (const auto& [a, b] : directed)
    if (!directed.count({b, a})) {
      border.emplace_back(a, b);
      m.triangles.push_back({a, b, lift(b)});
      m.triangles.push_back({a, lift(b), lift(a)});
    }
  // The lid, facing up: a fan from the border's centre when the border is one loop that is
  // star-shaped about it (a grid's rectangle, any convex border), so the lid has as many
  // triangles as the border edges; else the surface's own triangles lifted.
  const std::vector<std::int64_t> loop = border_loop(border);
  Vec2 c = Vec2::Zero();
  for (const std::int64_t v : loop) c += xy(up.vertices[std::size_t(v)]) / double(loop.size());
  const bool star = !loop.empty() && std::all_of(border.begin(), border.end(), [&](const auto& e) {
    const Vec2 a = xy(up.vertices[std::size_t(e.first)]) - c;
    const Vec2 b = xy(up.vertices[std::size_t(e.second)]) - c;
    return a.x() * b.y() - a.y() * b.x() > 1e-9 * a.norm() * b.norm();
  });
  if (star) {
    const auto centre = std::int64_t(m.vertices.size());
    m.vertices.emplace_back(c.x(), c.y(), top);
    for (const auto& [a, b] : border) m.triangles.push_back({centre, lift(a), lift(b)});
  } else {
    for (const auto& t : up.triangles) m.triangles.push_back({lift(t[0]), lift(t[1]), lift(t[2])});
  }
  return m;
}

}  // namespace slice
