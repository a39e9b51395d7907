-- sky_hdr.lua: writes a small equirectangular sky as a Radiance .hdr (RGBE)
-- file: a blue gradient from a pale horizon, a dim ground, a sun disc with
-- a glow around it. examples/assets/sky.hdr is this script's output; the
-- sky is made, not photographed, so the repository carries no image it did
-- not make, and the file stays small (256 x 128, flat RGBE: 131 KB).
--   lua5.4 tools/sky_hdr.lua [out.hdr] [width = 256]
--
-- The layout is lancer's (manual, "The sky and the background"): column u
-- is the azimuth atan2(d_x, d_z) (the middle column faces +z), row v the
-- elevation, the top row straight up. The sun: 2.5 degrees across at 35
-- degrees up, toward -x and -z; its radiance 3000 gives an irradiance of
-- about 3000 * pi * 0.0218^2 * sin 35 = 2.6 on the ground, the sky about
-- 1.6, so the sun casts plain shadows that the sky fills blue.
local out = arg[1] or "examples/assets/sky.hdr"
local W = math.tointeger(tonumber(arg[2] or 256))
assert(W and W >= 8 and W % 2 == 0, "width must be an even integer >= 8")
local H = W // 2

local SUN_EL, SUN_AZ = math.rad(35), math.rad(-130)
local SUN_RADIUS = math.rad(1.25)
local SUN = {3000, 2850, 2550}
local sun = {math.cos(SUN_EL) * math.sin(SUN_AZ), math.sin(SUN_EL),
             math.cos(SUN_EL) * math.cos(SUN_AZ)}

local function lerp(a, b, t) return {a[1] + (b[1] - a[1]) * t, a[2] + (b[2] - a[2]) * t,
                                     a[3] + (b[3] - a[3]) * t} end
local ZENITH, HORIZON, GROUND = {0.10, 0.25, 0.75}, {0.85, 0.9, 1.0}, {0.25, 0.22, 0.18}

-- Radiance toward unit direction d.
local function sky(d)
  local c
  if d[2] >= 0 then
    c = lerp(HORIZON, ZENITH, d[2] ^ 0.5)
  else
    c = lerp(HORIZON, GROUND, math.min(1, -d[2] * 8))
  end
  local cosg = d[1] * sun[1] + d[2] * sun[2] + d[3] * sun[3]
  local gamma = math.acos(math.max(-1, math.min(1, cosg)))
  if gamma < SUN_RADIUS then return SUN end
  local glow = 1.5 * math.exp(-gamma / math.rad(8))       -- the bright sky around the sun
  if d[2] < 0 then glow = 0 end
  return {c[1] + glow, c[2] + glow * 0.95, c[3] + glow * 0.8}
end

-- One RGBE pixel: the largest channel's exponent shared by all three.
local function rgbe(c)
  local m = math.max(c[1], c[2], c[3])
  if m < 1e-32 then return "\0\0\0\0" end
  local e = math.floor(math.log(m, 2)) + 1           -- m = f * 2^e, f in [0.5, 1)
  local scale = 256 / 2 ^ e
  local function byte(x) return math.min(255, math.floor(x * scale)) end
  return string.char(byte(c[1]), byte(c[2]), byte(c[3]), e + 128)
end

local rows = {("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n"):format(H, W)}
for j = 0, H - 1 do
  local el = (0.5 - (j + 0.5) / H) * math.pi
  local row = {}
  for i = 0, W - 1 do
    local az = ((i + 0.5) / W - 0.5) * 2 * math.pi
    local d = {math.cos(el) * math.sin(az), math.sin(el), math.cos(el) * math.cos(az)}
    row[i + 1] = rgbe(sky(d))
  end
  rows[#rows + 1] = table.concat(row)
end
local f = assert(io.open(out .. ".tmp", "wb"))
f:write(table.concat(rows))
assert(f:close())
assert(os.rename(out .. ".tmp", out))
print(("%s: %dx%d"):format(out, W, H))
