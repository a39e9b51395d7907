-- hdrsky.lua: a model under an HDR sky, lit by nothing else.
--
-- Two crates (examples/assets/crate.obj with its .mtl: planked sides, steel
-- caps), a white ball and a polished copper one on a grey ground, under
-- examples/assets/sky.hdr (tools/sky_hdr.lua makes it: a blue gradient,
-- a sun disc 35 degrees up). There are no lights: with indirect > 0 the
-- sky is the light, sampled by luminance so the sun is found at once; its
-- shadows fall toward the back and right, and the sky fills them blue, brightest
-- under the open side. With indirect = 0 the scene is black but for what
-- sees the sky itself.
--   build/bin/lancer scenes/hdrsky.lua [out.png] [samples = 64] [indirect = 4]
local lancer = require "lancer"
local here = (arg and arg[0] or ""):match("^(.*)/[^/]*$") or "."
local assets = here .. "/../examples/assets/"

local scene = lancer.scene{
  camera = lancer.camera{from = {1.8, 1.6, -4.2}, at = {0.1, 0.55, 0.3}, fov = 45},
  background = lancer.image_texture{path = assets .. "sky.hdr"},
  max_depth = 6,
}
scene:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                       material = lancer.material{color = {0.5, 0.5, 0.5}, kd = 1}})

local crate = lancer.load_obj(assets .. "crate.obj")
scene:add(crate:moved(lancer.rotate({0, 1, 0}, 25)),
          crate:moved(lancer.translate(0.2, 0, 0.1) * lancer.scale(0.6) *
                      lancer.rotate({0, 1, 0}, -10) * lancer.translate(0, 1.667, 0)))
scene:add(lancer.sphere{center = {-1.1, 0.45, -0.2}, radius = 0.45,
                        material = lancer.material{color = {0.9, 0.9, 0.9}, kd = 1}})
scene:add(lancer.sphere{center = {1.05, 0.35, -0.6}, radius = 0.35,
                        material = lancer.material{color = {0.95, 0.6, 0.4}, kd = 0.1,
                                                   kr = 0.8, glossiness = 30,
                                                   absorb = "all"}})

local out = arg and arg[1] or "hdrsky.png"
local samples = tonumber(arg and arg[2]) or 64
local indirect = tonumber(arg and arg[3]) or 4
local img, stats = scene:render{width = 320, height = 200, samples = samples,
                                indirect = indirect}
img:save(out, {tone = "filmic"})
print(("%s: %dx%d, %d samples, indirect %d, %.2f s"):format(out, img.width, img.height,
      samples, indirect, stats.seconds))
