-- lancer.preview: an image as text for a terminal, two pixels per cell:
-- the upper half block U+2580 with the top pixel as its foreground and the
-- bottom one as its background (docs/conventions.md 2). 24-bit colour
-- (ESC[38;2;R;G;B;48;2;R;G;Bm) when COLORTERM says truecolor or 24bit, else
-- the 256-colour cube (ESC[38;5;N;48;5;Nm).
local M = {}

local UPPER_HALF = "\u{2580}"

-- Linear to 8-bit sRGB, clamped, as img:save writes it.
local function srgb(v)
  if not (v > 0) then return 0 end
  if v >= 1 then return 255 end
  local s = v <= 0.0031308 and 12.92 * v or 1.055 * v ^ (1 / 2.4) - 0.055
  return math.floor(255 * s + 0.5)
end

-- The average of the image over the rectangle [x0, x1) x [y0, y1) (pixel
-- units from 0), from at most 4 x 4 of its pixels.
local function average(img, x0, x1, y0, y1)
  local nx = math.max(1, math.min(4, math.floor(x1 - x0)))
  local ny = math.max(1, math.min(4, math.floor(y1 - y0)))
  local r, g, b = 0, 0, 0
  for j = 0, ny - 1 do
    local y = math.min(img.height, math.floor(y0 + (j + 0.5) * (y1 - y0) / ny) + 1)
    for i = 0, nx - 1 do
      local x = math.min(img.width, math.floor(x0 + (i + 0.5) * (x1 - x0) / nx) + 1)
      local pr, pg, pb = img:pixel(x, y)
      r, g, b = r + pr, g + pg, b + pb
    end
  end
  local n = nx * ny
  return srgb(r / n), srgb(g / n), srgb(b / n)
end

local function cube(r, g, b)
  local function level(c) return math.floor(c / 255 * 5 + 0.5) end
  return 16 + 36 * level(r) + 6 * level(g) + level(b)
end

-- The size of the preview in cells: at most `columns` wide and `rows` high,
-- never wider than the image, pixels square (a cell is about twice as high
-- as it is wide, and holds two pixels one above the other).
function M.size(img, columns, rows)
  local w = math.min(columns, img.width)
  local h = math.max(1, math.floor(img.height * w / img.width + 0.5))
  if (h + 1) // 2 > rows then
    h = 2 * rows
    w = math.max(1, math.floor(img.width * h / img.height + 0.5))
  end
  return w, h
end

-- preview.text(img, {columns = 80, rows = 24, truecolor = true}) -> string
function M.text(img, opts)
  opts = opts or {}
  local w, h = M.size(img, opts.columns or 80, opts.rows or 24)
  local sx, sy = img.width / w, img.height / h
  local out = {}
  for cy = 0, (h + 1) // 2 - 1 do
    local line = {}
    for x = 0, w - 1 do
      local top, bottom = 2 * cy, 2 * cy + 1
      local r1, g1, b1 = average(img, x * sx, (x + 1) * sx, top * sy, (top + 1) * sy)
      if bottom < h then
        local r2, g2, b2 = average(img, x * sx, (x + 1) * sx, bottom * sy, (bottom + 1) * sy)
        if opts.truecolor == false then
          line[#line + 1] = ("\27[38;5;%d;48;5;%dm"):format(cube(r1, g1, b1), cube(r2, g2, b2))
        else
          line[#line + 1] = ("\27[38;2;%d;%d;%d;48;2;%d;%d;%dm"):format(r1, g1, b1, r2, g2, b2)
        end
      elseif opts.truecolor == false then      -- an odd last row: no bottom pixel
        line[#line + 1] = ("\27[38;5;%d;49m"):format(cube(r1, g1, b1))
      else
        line[#line + 1] = ("\27[38;2;%d;%d;%d;49m"):format(r1, g1, b1)
      end
      line[#line + 1] = UPPER_HALF
    end
    out[#out + 1] = table.concat(line) .. "\27[0m\n"
  end
  return table.concat(out)
end

-- Whether this environment wants colour at all: NO_COLOR set and not empty
-- (no-color.org) or TERM=dumb say no.
function M.wanted()
  local no = os.getenv("NO_COLOR")
  local term = os.getenv("TERM")
  return (no == nil or no == "") and term ~= nil and term ~= "dumb"
end

function M.truecolor()
  local ct = os.getenv("COLORTERM")
  return ct == "truecolor" or ct == "24bit"
end

return M
