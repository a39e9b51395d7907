-- lancer.plot: log-log line plots into PNG files, for `lancer --accuracy`.
-- gnuplot draws them when it is installed; otherwise (and on CI, which has
-- none) they are drawn here into a lancer image with a built-in 5x7 font,
-- so the report never depends on a tool that may be missing.
local M = {}

M.WIDTH, M.HEIGHT = 720, 450
local SCALE = 2                            -- font pixels per glyph pixel
local MARGIN = {left = 96, right = 36, top = 40, bottom = 64}

local WHITE, BLACK = {1, 1, 1}, {0, 0, 0}
local GRID = {0.75, 0.75, 0.75}            -- linear; light grey once sRGB-encoded
local DATA = {0.02, 0.12, 0.65}            -- blue
local SLOPE = {{0.8, 0.1, 0.02}, {0.05, 0.45, 0.05}}   -- red, green

-- The font: 7 rows of 5 pixels per glyph, capitals only (text is upper-cased).
local GLYPHS = {
  ["0"] = "01110 10001 10011 10101 11001 10001 01110",
  ["1"] = "00100 01100 00100 00100 00100 00100 01110",
  ["2"] = "01110 10001 00001 00010 00100 01000 11111",
  ["3"] = "11111 00010 00100 00010 00001 10001 01110",
  ["4"] = "00010 00110 01010 10010 11111 00010 00010",
  ["5"] = "11111 10000 11110 00001 00001 10001 01110",
  ["6"] = "00110 01000 10000 11110 10001 10001 01110",
  ["7"] = "11111 00001 00010 00100 01000 01000 01000",
  ["8"] = "01110 10001 10001 01110 10001 10001 01110",
  ["9"] = "01110 10001 10001 01111 00001 00010 01100",
  A = "01110 10001 10001 11111 10001 10001 10001",
  B = "11110 10001 10001 11110 10001 10001 11110",
  C = "01110 10001 10000 10000 10000 10001 01110",
  D = "11100 10010 10001 10001 10001 10010 11100",
  E = "11111 10000 10000 11110 10000 10000 11111",
  F = "11111 10000 10000 11110 10000 10000 10000",
  G = "01110 10001 10000 10111 10001 10001 01111",
  H = "10001 10001 10001 11111 10001 10001 10001",
  I = "01110 00100 00100 00100 00100 00100 01110",
  J = "00111 00010 00010 00010 00010 10010 01100",
  K = "10001 10010 10100 11000 10100 10010 10001",
  L = "10000 10000 10000 10000 10000 10000 11111",
  M = "10001 11011 10101 10101 10001 10001 10001",
  N = "10001 10001 11001 10101 10011 10001 10001",
  O = "01110 10001 10001 10001 10001 10001 01110",
  P = "11110 10001 10001 11110 10000 10000 10000",
  Q = "01110 10001 10001 10001 10101 10010 01101",
  R = "11110 10001 10001 11110 10100 10010 10001",
  S = "01111 10000 10000 01110 00001 00001 11110",
  T = "11111 00100 00100 00100 00100 00100 00100",
  U = "10001 10001 10001 10001 10001 10001 01110",
  V = "10001 10001 10001 10001 10001 01010 00100",
  W = "10001 10001 10001 10101 10101 10101 01010",
  X = "10001 10001 01010 00100 01010 10001 10001",
  Y = "10001 10001 10001 01010 00100 00100 00100",
  Z = "11111 00001 00010 00100 01000 10000 11111",
  [" "] = "00000 00000 00000 00000 00000 00000 00000",
  ["-"] = "00000 00000 00000 11111 00000 00000 00000",
  ["."] = "00000 00000 00000 00000 00000 01100 01100",
  [","] = "00000 00000 00000 00000 01100 00100 01000",
  [":"] = "00000 01100 01100 00000 01100 01100 00000",
  ["="] = "00000 00000 11111 00000 11111 00000 00000",
  ["/"] = "00000 00001 00010 00100 01000 10000 00000",
  ["("] = "00010 00100 01000 01000 01000 00100 00010",
  [")"] = "01000 00100 00010 00010 00010 00100 01000",
  ["+"] = "00000 00100 00100 11111 00100 00100 00000",
  ["%"] = "11000 11001 00010 00100 01000 10011 00011",
  ["_"] = "00000 00000 00000 00000 00000 00000 11111",
  ["?"] = "01110 10001 00001 00010 00100 00000 00100",
}
for ch, rows in pairs(GLYPHS) do          -- "01110 ..." -> {{x, y}, ...} lit pixels
  local lit, y = {}, 0
  for row in rows:gmatch("%d+") do
    for x = 1, 5 do
      if row:sub(x, x) == "1" then lit[#lit + 1] = {x - 1, y} end
    end
    y = y + 1
  end
  GLYPHS[ch] = lit
end

-- ---- Drawing on an image ------------------------------------------------------

local Canvas = {}
Canvas.__index = Canvas

local function canvas(w, h)
  local lancer = require "lancer"
  return setmetatable({img = lancer.image{width = w, height = h, color = WHITE},
                       w = w, h = h}, Canvas)
end

-- x, y 0-based, rounded; outside the image: ignored.
function Canvas:dot(x, y, c)
  x, y = math.floor(x + 0.5), math.floor(y + 0.5)
  if x >= 0 and x < self.w and y >= 0 and y < self.h then
    self.img:set(x + 1, y + 1, c[1], c[2], c[3])
  end
end

function Canvas:fill(x0, y0, x1, y1, c)
  for y = math.floor(y0 + 0.5), math.floor(y1 + 0.5) do
    for x = math.floor(x0 + 0.5), math.floor(x1 + 0.5) do self:dot(x, y, c) end
  end
end

-- A line `thick` pixels wide; dash = {on, off} in pixels along it, or nil.
-- clip = {x0, y0, x1, y1}: only the part inside is drawn.
function Canvas:line(x0, y0, x1, y1, c, thick, dash, clip)
  local n = math.max(1, math.ceil(math.max(math.abs(x1 - x0), math.abs(y1 - y0))))
  local r = (thick or 1) // 2
  for i = 0, n do
    local t = i / n
    local x, y = x0 + (x1 - x0) * t, y0 + (y1 - y0) * t
    local on = not dash or i % (dash[1] + dash[2]) < dash[1]
    local inside = not clip or (x >= clip[1] and x <= clip[3] and y >= clip[2] and
                                y <= clip[4])
    if on and inside then
      for dy = -r, (thick or 1) - 1 - r do
        for dx = -r, (thick or 1) - 1 - r do self:dot(x + dx, y + dy, c) end
      end
    end
  end
end

function M.text_width(s) return #s * 6 * SCALE - SCALE end
M.TEXT_HEIGHT = 7 * SCALE

-- Text with its top-left at x, y; vertical: turned a quarter left, reading
-- upward from x, y (its bottom-left).
function Canvas:text(x, y, s, c, vertical)
  s = s:upper()
  for i = 1, #s do
    local g = GLYPHS[s:sub(i, i)] or GLYPHS["?"]
    local off = (i - 1) * 6 * SCALE
    for _, p in ipairs(g) do
      for sy = 0, SCALE - 1 do
        for sx = 0, SCALE - 1 do
          local gx, gy = off + p[1] * SCALE + sx, p[2] * SCALE + sy
          if vertical then
            self:dot(x + gy, y - gx, c)
          else
            self:dot(x + gx, y + gy, c)
          end
        end
      end
    end
  end
end

-- ---- The plot -----------------------------------------------------------------

local function log10(x) return math.log(x, 10) end

-- "%g" for a power of ten: 0.001, 0.01, 1, 10, 1e+06.
local function decade_label(e)
  return ("%g"):format(10.0 ^ e)
end

-- Whole decades around [lo, hi], at least one.
local function decades(lo, hi)
  local a, b = math.floor(log10(lo) + 1e-9), math.ceil(log10(hi) - 1e-9)
  if b <= a then b = a + 1 end
  return a, b
end

-- The frame's grid at decades, ticks at 2..9 times them, labels at
-- decades, and its border; e: the decades {x0, x1, y0, y1}, box: the frame's
-- pixels {x0, y0, x1, y1}.
local function draw_axes(cv, frame, e, box)
  local ex0, ex1, ey0, ey1 = e[1], e[2], e[3], e[4]
  local px0, py0, px1, py1 = box[1], box[2], box[3], box[4]
  for d = ex0, ex1 do
    local x = frame.map(10.0 ^ d, 10.0 ^ ey0)
    if d > ex0 and d < ex1 then cv:line(x, py0, x, py1, GRID) end
    local s = decade_label(d)
    cv:text(x - M.text_width(s) / 2, py1 + 8, s, BLACK)
    for k = 2, 9 do
      if d < ex1 then
        local xm = frame.map(k * 10.0 ^ d, 10.0 ^ ey0)
        cv:line(xm, py1 - 3, xm, py1, BLACK)
      end
    end
  end
  for d = ey0, ey1 do
    local _, y = frame.map(10.0 ^ ex0, 10.0 ^ d)
    if d > ey0 and d < ey1 then cv:line(px0, y, px1, y, GRID) end
    local s = decade_label(d)
    cv:text(px0 - 8 - M.text_width(s), y - M.TEXT_HEIGHT / 2, s, BLACK)
    for k = 2, 9 do
      if d < ey1 then
        local _, ym = frame.map(10.0 ^ ex0, k * 10.0 ^ d)
        cv:line(px0, ym, px0 + 3, ym, BLACK)
      end
    end
  end
  cv:line(px0, py0, px0, py1, BLACK)
  cv:line(px0, py1, px1, py1, BLACK)
  cv:line(px1, py0, px1, py1, BLACK)
  cv:line(px0, py0, px1, py0, BLACK)
end

-- Reference slopes through the first point, across the whole frame; then
-- the data: a line through the points, a square on each, its label.
local function draw_data(cv, frame, spec, pts, e, clip)
  if #pts > 0 then
    for i, s in ipairs(spec.slopes or {}) do
      local p = pts[1]
      local xa, xb = 10.0 ^ e[1], 10.0 ^ e[2]
      local ya, yb = p.y * (xa / p.x) ^ s[1], p.y * (xb / p.x) ^ s[1]
      local ax, ay = frame.map(xa, ya)
      local bx, by = frame.map(xb, yb)
      cv:line(ax, ay, bx, by, SLOPE[(i - 1) % #SLOPE + 1], 2, {8, 6}, clip)
    end
  end
  for i = 2, #pts do
    local ax, ay = frame.map(pts[i - 1].x, pts[i - 1].y)
    local bx, by = frame.map(pts[i].x, pts[i].y)
    cv:line(ax, ay, bx, by, DATA, 2, nil, clip)
  end
  for _, p in ipairs(pts) do
    local x, y = frame.map(p.x, p.y)
    cv:fill(x - 4, y - 4, x + 4, y + 4, DATA)
    if p.label then cv:text(x + 8, y - 8 - M.TEXT_HEIGHT, p.label, BLACK) end
  end
end

-- How much of the plot a legend box bw x bh at corner {x, y} would hide
-- (grid lines do not count): a measured point or its label counts as much
-- as a whole line.
local function hidden_by(cv, frame, pts, corner, bw, bh)
  local hidden = 0
  for _, pt in ipairs(pts) do
    local x, y = frame.map(pt.x, pt.y)
    local x1 = x + 8 + (pt.label and M.text_width(pt.label) or 0)
    if x1 >= corner[1] and x - 4 <= corner[1] + bw and y + 4 >= corner[2] and
       y - 8 - M.TEXT_HEIGHT <= corner[2] + bh then
      hidden = hidden + 1e6
    end
  end
  for y = corner[2], corner[2] + bh, 2 do
    for x = corner[1], corner[1] + bw, 2 do
      local r, g, b = cv.img:pixel(math.floor(x) + 1, math.floor(y) + 1)
      if r ~= g or g ~= b or (r < 0.7 and r ~= 1) then hidden = hidden + 1 end
    end
  end
  return hidden
end

-- The legend, on a white box in the corner of the frame that hides the
-- least of the plot.
local function draw_legend(cv, frame, spec, pts, box)
  local px0, py0, px1, py1 = box[1], box[2], box[3], box[4]
  local entries = {{spec.series or "measured", DATA}}
  for i, s in ipairs(spec.slopes or {}) do
    entries[#entries + 1] = {s[2], SLOPE[(i - 1) % #SLOPE + 1], true}
  end
  local lw = 0
  for _, e in ipairs(entries) do lw = math.max(lw, M.text_width(e[1])) end
  local bw, bh = lw + 52, #entries * (M.TEXT_HEIGHT + 6) + 10
  local best, lx, ly = math.huge, nil, nil
  for _, corner in ipairs{{px1 - 6 - bw, py0 + 6}, {px0 + 6, py1 - 6 - bh},
                          {px0 + 6, py0 + 6}, {px1 - 6 - bw, py1 - 6 - bh}} do
    local hidden = hidden_by(cv, frame, pts, corner, bw, bh)
    if hidden < best then best, lx, ly = hidden, corner[1], corner[2] end
  end
  cv:fill(lx, ly, lx + bw, ly + bh, WHITE)
  cv:line(lx, ly, lx + bw, ly, BLACK)
  cv:line(lx, ly + bh, lx + bw, ly + bh, BLACK)
  cv:line(lx, ly, lx, ly + bh, BLACK)
  cv:line(lx + bw, ly, lx + bw, ly + bh, BLACK)
  for i, e in ipairs(entries) do
    local y = ly + 6 + (i - 1) * (M.TEXT_HEIGHT + 6)
    cv:line(lx + 8, y + M.TEXT_HEIGHT / 2, lx + 36, y + M.TEXT_HEIGHT / 2, e[2], 2,
            e[3] and {8, 6} or nil)
    cv:text(lx + 44, y, e[1], BLACK)
  end
end

-- Draws the plot; returns the canvas and frame.map(x, y) -> pixel x, y
-- (0-based), so tests can find where things are.
-- spec: {title, xlabel, ylabel, points = {{x, y, label}}, slopes = {{s, label}}}
-- Slope lines go through the first point. Points with x or y <= 0 (or NaN)
-- cannot be placed on log axes and are left out.
function M.draw(spec)
  local cv = canvas(spec.width or M.WIDTH, spec.height or M.HEIGHT)
  local pts = {}
  for _, p in ipairs(spec.points) do
    if p.x > 0 and p.y > 0 and p.x < math.huge and p.y < math.huge then
      pts[#pts + 1] = p
    end
  end
  local px0, py0 = MARGIN.left, MARGIN.top
  local px1, py1 = cv.w - 1 - MARGIN.right, cv.h - 1 - MARGIN.bottom
  local xlo, xhi, ylo, yhi = math.huge, 0, math.huge, 0
  for _, p in ipairs(pts) do
    xlo, xhi = math.min(xlo, p.x), math.max(xhi, p.x)
    ylo, yhi = math.min(ylo, p.y), math.max(yhi, p.y)
  end
  if #pts == 0 then xlo, xhi, ylo, yhi = 1, 10, 1, 10 end
  local ex0, ex1 = decades(xlo, xhi)
  local ey0, ey1 = decades(ylo, yhi)
  local frame = {}
  function frame.map(x, y)
    return px0 + (log10(x) - ex0) / (ex1 - ex0) * (px1 - px0),
           py1 - (log10(y) - ey0) / (ey1 - ey0) * (py1 - py0)
  end
  local box = {px0, py0, px1, py1}
  draw_axes(cv, frame, {ex0, ex1, ey0, ey1}, box)
  draw_data(cv, frame, spec, pts, {ex0, ex1, ey0, ey1}, box)
  if spec.title then
    cv:text((cv.w - M.text_width(spec.title)) / 2, 12, spec.title, BLACK)
  end
  if spec.xlabel then
    cv:text((px0 + px1 - M.text_width(spec.xlabel)) / 2, py1 + 34, spec.xlabel, BLACK)
  end
  if spec.ylabel then
    cv:text(14, (py0 + py1 + M.text_width(spec.ylabel)) / 2, spec.ylabel, BLACK, true)
  end
  draw_legend(cv, frame, spec, pts, box)
  return cv, frame
end

local function quote(s) return "'" .. s:gsub("'", [['\'']]) .. "'" end

local function gnuplot_string(s) return '"' .. s:gsub('[\\"]', "\\%0") .. '"' end

-- The same plot by gnuplot; the script is kept beside the PNG (path .. ".gp")
-- so it can be edited and re-run. Returns true when gnuplot wrote the file.
local function by_gnuplot(spec)
  local pts = {}
  for _, p in ipairs(spec.points) do
    if p.x > 0 and p.y > 0 and p.x < math.huge and p.y < math.huge then
      pts[#pts + 1] = p
    end
  end
  if #pts == 0 then return false end
  local lines = {
    ("set terminal pngcairo size %d,%d"):format(M.WIDTH, M.HEIGHT),
    "set output " .. gnuplot_string(spec.path),
    "set logscale xy", "set grid", "set key top right",
    "set title " .. gnuplot_string(spec.title or ""),
    "set xlabel " .. gnuplot_string(spec.xlabel or ""),
    "set ylabel " .. gnuplot_string(spec.ylabel or ""),
    "$data << EOD",
  }
  for _, p in ipairs(pts) do
    lines[#lines + 1] = ("%.9g %.9g %s"):format(p.x, p.y, p.label or "")
  end
  lines[#lines + 1] = "EOD"
  local plots = {"$data using 1:2 with linespoints pt 5 title " ..
                 gnuplot_string(spec.series or "measured"),
                 "$data using 1:2:3 with labels offset 1.5,1 notitle"}
  for _, s in ipairs(spec.slopes or {}) do
    plots[#plots + 1] = ("%.9g * (x / %.9g) ** (%g) dt 2 title %s"):format(
      pts[1].y, pts[1].x, s[1], gnuplot_string(s[2]))
  end
  lines[#lines + 1] = "plot " .. table.concat(plots, ", \\\n     ")
  local gp = spec.path .. ".gp"
  local f = io.open(gp, "w")
  if not f then return false end
  f:write(table.concat(lines, "\n"), "\n")
  f:close()
  os.remove(spec.path)
  local ok = os.execute("gnuplot " .. quote(gp) .. " > /dev/null 2>&1")
  local png = io.open(spec.path, "rb")
  if png then png:close() end
  return ok == true and png ~= nil
end

-- Writes the plot to spec.path. spec as for draw, plus own = true to skip
-- gnuplot. Returns how it was drawn: "gnuplot" or "own plot".
function M.loglog(spec)
  if not spec.own and os.execute("command -v gnuplot > /dev/null 2>&1") == true and
     by_gnuplot(spec) then
    return "gnuplot"
  end
  local cv = M.draw(spec)
  cv.img:save(spec.path)
  return "own plot"
end

return M
