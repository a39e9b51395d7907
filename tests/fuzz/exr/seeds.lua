-- seeds.lua: writes the EXR harness's seed corpus (tests/fuzz/exr/corpus/)
-- with lancer's own writer: small images of half and float samples, every
-- compression, scanlines and tiles, with and without alpha, and a render
-- whose AOVs are layers of the file. Run from the repository's top with
-- the lancer command (lancer tests/fuzz/exr/seeds.lua); the files are
-- committed, so this only needs running to change them.
local lancer = require "lancer"

local OUT = "tests/fuzz/exr/corpus"
local W, H = 5, 3                      -- odd sizes: partial tiles and chunks

local img = lancer.image{width = W, height = H, color = {0, 0, 0}}
for y = 1, H do
  for x = 1, W do
    img:set(x, y, x / W, y / H, (x + y) % 3 - 0.5)
  end
end

local s = lancer.scene{camera = lancer.camera{from = {0, 0, -3}, at = {0, 0, 0}},
                       ambient = 1}
s:add(lancer.sphere{center = {0, 0, 0}, radius = 1})
local cut = s:render{width = W, height = H, alpha = true}   -- the sphere's edge

local kinds = {
  {"half_zip", img, {pixel = "half", compression = "zip"}},
  {"half_piz_alpha", cut, {pixel = "half", compression = "piz", alpha = true}},
  {"half_rle_tile2", img, {pixel = "half", compression = "rle", tile = 2}},
  {"half_none", img, {pixel = "half", compression = "none"}},
  {"float_zips", img, {pixel = "float", compression = "zips"}},
  {"float_none_tile4_alpha", cut, {pixel = "float", compression = "none", tile = 4,
                                   alpha = true}},
  {"float_piz_tile2", img, {pixel = "float", compression = "piz", tile = 2}},
}
for _, k in ipairs(kinds) do
  k[2]:save(OUT .. "/" .. k[1] .. ".exr", k[3])
end

local r = s:render{width = 4, height = 3, aovs = {"depth", "normal"}}
r:save(OUT .. "/aovs_half_none.exr", {compression = "none"})
