-- optics.lua: what the glass tests (test_hard.lua, test_glass.lua) expect,
-- worked out here: Fresnel, Snell, light through interfaces met head-on,
-- and the scene parts they build.
local lancer = require "lancer"

local M = {}

local function add(a, b) return {a[1] + b[1], a[2] + b[2], a[3] + b[3]} end
local function sub(a, b) return {a[1] - b[1], a[2] - b[2], a[3] - b[3]} end
local function mul(a, s) return {a[1] * s, a[2] * s, a[3] * s} end
local function madd(a, b, s) return {a[1] + b[1] * s, a[2] + b[2] * s, a[3] + b[3] * s} end
local function dot(a, b) return a[1] * b[1] + a[2] * b[2] + a[3] * b[3] end
local function norm(a) return mul(a, 1 / math.sqrt(dot(a, a))) end
local function cross(a, b)
  return {a[2] * b[3] - a[3] * b[2], a[3] * b[1] - a[1] * b[3], a[1] * b[2] - a[2] * b[1]}
end

-- Clear glass: no diffuse and no ambient term (kd and ka default to 1), all
-- of it reflected and transmitted by the Fresnel equations; t overrides.
function M.glass(t)
  local m = {kd = 0, ka = 0, kt = 1, ior = 1.5}
  for k, v in pairs(t or {}) do m[k] = v end
  return lancer.material(m)
end

-- A surface that only glows, radiance L.
function M.glow(L) return lancer.material{kd = 0, ka = 0, emission = L} end

-- The exact unpolarised Fresnel reflectance at cosine c on the ray's side,
-- eta = n_t / n_i (1 past the critical angle).
function M.fresnel(c, eta)
  local s2 = (1 - c) * (1 + c) / (eta * eta)
  if s2 >= 1 then return 1 end
  local ct = math.sqrt(1 - s2)
  local rp = (eta * c - ct) / (eta * c + ct)
  local rs = (c - eta * ct) / (c + eta * ct)
  return (rp * rp + rs * rs) / 2
end

-- Unit d refracted at unit n (facing d), eta = n_t / n_i; nil past the
-- critical angle.
function M.refract(d, n, eta)
  local c = -dot(d, n)
  local s2 = (1 - c) * (1 + c) / (eta * eta)
  if s2 >= 1 then return nil end
  return norm(madd(mul(d, 1 / eta), n, c / eta - math.sqrt(1 - s2)))
end

-- Light along a line through flat interfaces met head-on, as the renderer's
-- tree traces it: the camera ray (depth 0) meets interface 1; each
-- interaction spawns a reflected and a transmitted ray one deeper while the
-- depth is under max_depth; a ray that leaves past the last interface sees
-- `ahead`, one that comes back out the first sees `behind`. ifaces[k] =
-- {ratio n_t / n_i going forward, distance to interface k + 1, absorption
-- along it}. Returns the pixel, for cutoff = 0.
function M.chain(ifaces, max_depth, ahead, behind)
  local function seg(j)               -- what crossing from interface j to j + 1 leaves
    local g = ifaces[j]
    return g and math.exp(-(g[3] or 0) * g[2]) or 1
  end
  -- rays[k][dir]: the weight meeting interface k going dir (+1 or -1) at
  -- this depth; one interface per bounce, so the sweep is linear in depth
  local total, rays = 0, {[1] = {[1] = 1}}
  for depth = 0, max_depth do
    local next = {}
    local function put(k, dir, w)
      next[k] = next[k] or {}
      next[k][dir] = (next[k][dir] or 0) + w
    end
    for k, dirs in pairs(rays) do
      for dir, w in pairs(dirs) do
        if k > #ifaces then
          total = total + w * ahead
        elseif k < 1 then
          total = total + w * behind
        elseif depth < max_depth then
          local ratio = dir > 0 and ifaces[k][1] or 1 / ifaces[k][1]
          local R = M.fresnel(1, ratio)
          local back, on = dir > 0 and seg(k - 1) or seg(k), dir > 0 and seg(k) or seg(k - 1)
          put(k - dir, -dir, w * R * back)
          put(k + dir, dir, w * (1 - R) * on)
        end
      end
    end
    rays = next
  end
  return total
end

-- A closed prism: the triangle tri ({x, z} each) swept over y in [y0, y1],
-- every face wound counter-clockwise seen from outside (normals out).
function M.prism(tri, y0, y1, material)
  local v, c = {}, {0, 0, 0}
  for i, p in ipairs(tri) do
    v[i], v[i + 3] = {p[1], y0, p[2]}, {p[1], y1, p[2]}
  end
  for _, p in ipairs(v) do c = madd(c, p, 1 / 6) end
  local faces = {{1, 2, 3}, {4, 5, 6}, {1, 2, 5}, {1, 5, 4}, {2, 3, 6}, {2, 6, 5},
                 {3, 1, 4}, {3, 4, 6}}
  for _, f in ipairs(faces) do
    local a, b, d = v[f[1]], v[f[2]], v[f[3]]
    local mid = mul(add(add(a, b), d), 1 / 3)
    if dot(cross(sub(b, a), sub(d, a)), sub(mid, c)) < 0 then f[2], f[3] = f[3], f[2] end
  end
  return lancer.mesh{vertices = v, faces = faces, material = material}
end

-- A camera far down -z looking at the origin whose image spans half-width
-- `half` there: its rays are parallel within half / 1e4. Returns the
-- lancer camera and the table it was made from.
function M.far_camera(half, dist)
  dist = dist or 1e4
  local t = {from = {0, 0, -dist}, at = {0, 0, 0},
             fov = 2 * math.deg(math.atan(half / dist))}
  return lancer.camera(t), t
end

-- The records of a ray tree, depth first.
function M.records(tree, out)
  out = out or {}
  out[#out + 1] = tree
  for _, r in ipairs(tree.rays or {}) do M.records(r, out) end
  return out
end

return M
