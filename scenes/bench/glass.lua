-- glass.lua: the bench's glass-and-checker scene, after Whitted's 1980
-- picture: a glass sphere (ior 1.5) and a mirror sphere over a checker
-- floor, one point light, a uniform background. The same scene as
-- tools/bench/scenes.lua's glass, which `make bench` writes for POV-Ray 3.7
-- (docs/bench-scenes.md's conventions: no light falloff, POV-Ray's colouring, 1280x720,
-- linear output).
-- Usage: lancer scenes/bench/glass.lua [samples] [out.png]
-- Prints one line to stderr: bench glass lua=<s> build=<s> trace=<s> rays=<n> ...
--
-- The glass is the seed's fixed model (fresnel = false): it reflects kr and
-- transmits kt whatever the angle, and at a total internal reflection sends
-- kr + kt = 1 back. POV-Ray 3.7 draws exactly that (a fixed reflection, a
-- transmit of kt, its total internal reflection at full weight), and its
-- shadow rays keep kt at each glass surface, as lancer's filtered ones do
-- without Fresnel. With Fresnel on both sides (kt = 1; POV-Ray's
-- reflection { 0, 1 fresnel on } and conserve_energy) the images part:
-- POV-Ray's shadow rays take no Fresnel share, so the shadow under the glass
-- is lighter, and the sphere itself differs too (measured: mean 1.0/255,
-- 92.6 % of pixels within 2/255). max_depth 5 and cutoff 0: both renderers
-- trace the whole tree to 5 bounces (POV-Ray's max_trace_level 6,
-- adc_bailout 0) and nothing past it.
local lancer = require "lancer"
local samples = tonumber(arg and arg[1]) or 1
local out = arg and arg[2]
local t0 = os.clock()

-- absorb = 'diffuse': the colour scales ambient and diffuse only (POV-Ray's model).
local board = lancer.checker{a = {0.95, 0.85, 0.1}, b = {0.9, 0.1, 0.05}, scale = 1}
local floor = lancer.material{color = board, ka = 0.1, kd = 0.8, absorb = "diffuse"}
local mirror = lancer.material{color = 1, ka = 0, kd = 0, kr = 0.9, absorb = "diffuse"}
local glass = lancer.material{color = 1, ka = 0, kd = 0, kr = 0.1, kt = 0.9, ior = 1.5,
                              fresnel = false, absorb = "diffuse"}

local scene = lancer.scene{
  camera = lancer.camera{from = {0, 1.7, -6.5}, at = {0, 0.5, 0}, fov = 55},
  background = {0.3, 0.5, 0.85}, ambient = 1, max_depth = 5}
-- Half-way through a layer of the checker's unit cubes: no point of the
-- floor lies on a cube's face, where either colour could win.
scene:add(lancer.plane{point = {0, -0.5, 0}, normal = {0, 1, 0}, material = floor})
scene:add(lancer.sphere{center = {-0.7, 0.52, -1.0}, radius = 1.0, material = glass})
scene:add(lancer.sphere{center = {1.6, 0.62, 1.2}, radius = 1.1, material = mirror})
-- A point light as POV-Ray's: no distance falloff.
scene:add(lancer.point_light{position = {-4, 7, -5}, color = 1, falloff = "none"})
local lua_seconds = os.clock() - t0

local img, stats = scene:render{width = 1280, height = 720, samples = samples,
                                cutoff = 0}
if out then img:save(out, {encoding = "linear"}) end
local rays = 0
for _, n in pairs(stats.rays) do rays = rays + n end
io.stderr:write(("bench glass " ..
  "lua=%.4f build=%.4f trace=%.4f rays=%d nodes=%d prims=%d refraction=%d\n"):format(
  lua_seconds, stats.compile_seconds, stats.trace_seconds, rays, stats.bvh_nodes,
  stats.primitives, stats.rays.refraction))
