-- checker_aa.lua: how well pixel samples anti-alias a checker floor running
-- to the horizon (issue 12 item 2): the error of 1, 4, 16 and 64 samples
-- per pixel against a reference of REF samples, by the distance the rows
-- see, and the largest error of any band of rows (a moire band shows as a
-- row band far worse than its neighbours).
--   build/bin/lancer tools/measure/checker_aa.lua [REF] [WIDTH]
local lancer = require "lancer"
local REF = tonumber(arg and arg[1]) or 1024
local W = tonumber(arg and arg[2]) or 240
local H = W // 2

local function scene()
  local s = lancer.scene{camera = lancer.camera{from = {0, 1, 0}, at = {0, 0.78, 10},
                                                fov = 70}, ambient = 1,
                         background = {0.5, 0.5, 0.5}}
  local board = lancer.checker{a = {1, 1, 1}, b = {0, 0, 0}, scale = 0.5}
  s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                     material = lancer.material{color = board, ka = 1, kd = 0}})
  return s
end

local s = scene()
local t0 = os.clock()
local ref = s:render{width = W, height = H, samples = REF}
io.write(("reference: %d samples per pixel, %dx%d, %.1f s of CPU\n"):format(REF, W, H,
         os.clock() - t0))
-- Distance along the floor of each row's centre ray (nil above the horizon).
local dist = {}
for y = 1, H do
  local tree = s:explain{x = W // 2, y = y, width = W, height = H}
  dist[y] = tree.hit and tree.hit.distance or nil
end
local bands = {{0, 2}, {2, 4}, {4, 8}, {8, 16}, {16, 32}, {32, 1e9}}
io.write("| spp | time (s) |")
for _, b in ipairs(bands) do
  io.write((" RMSE at %s |"):format(b[2] < 1e9 and ("%g-%g"):format(b[1], b[2]) or
                                    (">%g"):format(b[1])))
end
io.write(" worst row (its distance) |\n|---|---|")
for _ = 1, #bands do io.write("---|") end
io.write("---|\n")
for _, spp in ipairs{1, 4, 16, 64} do
  local c0 = os.clock()
  local img, st = s:render{width = W, height = H, samples = spp}
  local secs = st.trace_seconds
  local sum, n = {}, {}
  local worst, worst_y = 0, 0
  for y = 1, H do
    if dist[y] then
      local e = 0
      for x = 1, W do
        local a = img:pixel(x, y)
        local b = ref:pixel(x, y)
        e = e + (a - b) ^ 2
      end
      e = e / W
      if math.sqrt(e) > worst then worst, worst_y = math.sqrt(e), y end
      for k, b in ipairs(bands) do
        if dist[y] >= b[1] and dist[y] < b[2] then
          sum[k] = (sum[k] or 0) + e
          n[k] = (n[k] or 0) + 1
        end
      end
    end
  end
  io.write(("| %d | %.3f |"):format(spp, secs))
  for k = 1, #bands do
    io.write(n[k] and (" %.4f |"):format(math.sqrt(sum[k] / n[k])) or " - |")
  end
  io.write((" %.4f (%.1f) |\n"):format(worst, dist[worst_y] or 0))
  local _ = c0
end
