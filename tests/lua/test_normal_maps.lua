-- test_normal_maps.lua: tangent-space normal maps on mesh faces with uvs,
-- against the closed form of a diffuse floor under a sun: E / pi (n . l)
-- with n the map's normal in the face's (dp/du, dp/dv, N) frame.
local T = require "harness"
local lancer = require "lancer"

local PI = math.pi
local E = 2                         -- the sun's irradiance

-- A constant normal map of tangent-space normal n (a unit vector).
local function map_of(n)
  local img = lancer.image{width = 2, height = 2,
                           color = {(n[1] + 1) / 2, (n[2] + 1) / 2, (n[3] + 1) / 2}}
  return lancer.image_texture{image = img, mapping = "uv"}
end

-- A floor in y = 0 over [-1, 1]^2, its normal up, u along +x (or -x when
-- mirror_u) and v along +z; a sun shining toward -l; what the centre
-- pixel reads, seen from straight above.
local function floor_pixel(l, material, mirror_u, moved)
  local u0, u1 = 0, 1
  if mirror_u then u0, u1 = 1, 0 end
  local mesh = lancer.mesh{vertices = {{-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}},
                           uvs = {{u0, 0}, {u0, 1}, {u1, 1}, {u1, 0}},
                           faces = {{1, 2, 3, 4}}, material = material}
  local from, at, up = {0.1, 3, 0.2}, {0.1, 0, 0.2}, {0, 0, 1}
  if moved then
    from, at, up = moved:apply(from), moved:apply(at), moved:apply_vector(up)
  end
  local s = lancer.scene{camera = lancer.camera{from = from, at = at, up = up, fov = 10}}
  local sun = lancer.directional_light{direction = {-l[1], -l[2], -l[3]}, irradiance = E}
  if moved then
    s:add(mesh:moved(moved), sun:moved(moved))
  else
    s:add(mesh, sun)
  end
  local img = s:render{width = 1, height = 1}
  return (img:pixel(1, 1))
end

local function unit(x, y, z)
  local n = math.sqrt(x * x + y * y + z * z)
  return {x / n, y / n, z / n}
end

-- E / pi max(0, n . l), n the tangent-space normal (x, y, z) scaled by k
-- in its tangent components, in the world frame (T, B, N) = (+x, +z, +y).
local function want(n, k, l, sign_t)
  local w = unit(sign_t * k * n[1], n[3], k * n[2])
  return E / PI * math.max(0, w[1] * l[1] + w[2] * l[2] + w[3] * l[3])
end

local tilt = math.rad(30)
local toward_u = {math.sin(tilt), 0, math.cos(tilt)}     -- leans along dp/du
local toward_v = {0, math.sin(tilt), math.cos(tilt)}     -- leans along dp/dv
local from_px = unit(math.sin(math.rad(40)), math.cos(math.rad(40)), 0)
local from_nx = unit(-math.sin(math.rad(40)), math.cos(math.rad(40)), 0)
local from_pz = unit(0, math.cos(math.rad(40)), math.sin(math.rad(40)))

T.test("a flat map (0.5, 0.5, 1) leaves the normal exactly as it was", function()
  local plain = floor_pixel(from_px, lancer.material{kd = 1})
  local flat = floor_pixel(from_px, lancer.material{kd = 1, normal_map = map_of{0, 0, 1}})
  T.eq(flat, plain, "bit for bit")
  T.near(plain, E / PI * from_px[2], 1e-7, "the floor's own E/pi cos")
end)

T.test("red leans the normal along dp/du, green along dp/dv", function()
  for _, c in ipairs{
    {toward_u, from_px, "u-lean, light from +x"},
    {toward_u, from_nx, "u-lean, light from -x"},
    {toward_v, from_pz, "v-lean, light from +z"},
    {toward_v, from_px, "v-lean, light from +x"},
  } do
    local got = floor_pixel(c[2], lancer.material{kd = 1, normal_map = map_of(c[1])})
    T.near(got, want(c[1], 1, c[2], 1), 2e-7, c[3])
  end
  -- Leaning toward the light brightens, away darkens.
  local m = lancer.material{kd = 1, normal_map = map_of(toward_u)}
  assert(floor_pixel(from_px, m) > floor_pixel(from_nx, m), "toward the light is brighter")
end)

T.test("a mirrored uv layout leans the other way in the world", function()
  local m = lancer.material{kd = 1, normal_map = map_of(toward_u)}
  T.near(floor_pixel(from_px, m, true), want(toward_u, 1, from_px, -1), 2e-7, "u mirrored")
  T.near(floor_pixel(from_px, m, true), floor_pixel(from_nx, m), 2e-7,
         "as the unmirrored floor lit from the mirrored side")
end)

T.test("normal_scale scales the tangent components; 0 is flat", function()
  local n = toward_u
  for _, k in ipairs{0, 0.5, 2} do
    local m = lancer.material{kd = 1, normal_map = map_of(n), normal_scale = k}
    T.near(floor_pixel(from_nx, m), want(n, k, from_nx, 1), 2e-7, "k = " .. k)
  end
  T.eq(lancer.material{normal_map = map_of(n)}.normal_scale, 1, "default 1")
end)

T.test("the map follows a moved mesh: same pixel under a rotation", function()
  local m = lancer.material{kd = 1, normal_map = map_of(toward_u)}
  local r = lancer.rotate({0.3, 1, 0.2}, 37) * lancer.translate(2, -1, 0.5)
  T.near(floor_pixel(from_px, m, false, r), floor_pixel(from_px, m), 1e-9, "rotated")
end)

T.test("a PNG normal map read with encoding = 'linear' keeps its stored values", function()
  local path = os.tmpname() .. ".png"
  local img = lancer.image{width = 1, height = 1, color = {0.5, 0.5, 1}}
  img:save(path, {encoding = "linear"})
  -- The stored bytes 128, 128, 255 read back as data, not as sRGB.
  local mat = lancer.material{ka = 1, kd = 0,
                              color = lancer.image_texture{path = path, encoding = "linear"}}
  local s = lancer.scene{camera = lancer.camera{from = {0, 3, 0}, at = {0, 0, 0},
                                                up = {0, 0, 1}}, ambient = 1}
  s:add(lancer.mesh{vertices = {{-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}},
                    uvs = {{0, 0}, {0, 1}, {1, 1}, {1, 0}}, faces = {{1, 2, 3, 4}},
                    material = mat})
  local r, g, b = s:render{width = 1, height = 1}:pixel(1, 1)
  T.near(r, 128 / 255, 1e-7, "r"); T.near(g, 128 / 255, 1e-7, "g"); T.near(b, 1, 1e-7, "b")
  local srgb = lancer.image_texture{path = path}
  T.eq(srgb.encoding, nil, "no such field is kept on the texture")
  os.remove(path)
end)

T.test("normal maps: errors name the field", function()
  T.check_error(function() lancer.material{normal_map = 3} end, "field 'normal_map'")
  T.check_error(function() lancer.material{normal_map = map_of{0, 0, 1}, normal_scale = -1} end,
           "field 'normal_scale'")
  T.check_error(function() lancer.material{normal_scale = 0 / 0} end, "field 'normal_scale'")
  T.check_error(function() lancer.image_texture{path = "x.png", encoding = "gamma"} end,
           "field 'encoding'")
end)
