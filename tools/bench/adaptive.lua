-- adaptive.lua: docs/numerics.md T7, adaptive sampling reaches the RMSE of
-- uniform 256 samples per pixel in at most half the time, without bias.
--
-- The scene is the T7 test's (tests/lua/test_sampling.lua) at a larger
-- size: 80 % flat sky, a glossy sphere (one cone ray per hit) on a floor
-- lit by a small emissive sphere (one light sample per hit), so all the
-- noise is in a fifth of the pixels. Rendered in this process (bench.lua
-- runs under lancer); the reference is 4096 samples per pixel with its own
-- seed; times are trace seconds, medians of interleaved runs.
local lancer = require "lancer"

local M = {}

M.NOISE, M.MAX = 0.1, 1024

function M.scene()
  local s = lancer.scene{camera = lancer.camera{from = {0, 1, -6}, at = {0, 0.4, 0}, fov = 30},
                         background = {0.2, 0.3, 0.5}}
  s:add(lancer.quad{corner = {-0.6, 0, -0.6}, u = {1.2, 0, 0}, v = {0, 0, 1.2},
                    material = lancer.material{}})
  s:add(lancer.sphere{center = {0, 0.35, 0}, radius = 0.35,
                      material = lancer.material{kd = 0.3, kr = 0.6, glossiness = 15,
                                                 cone_samples = 1}})
  s:add(lancer.sphere{center = {0.8, 1.6, -0.5}, radius = 0.3,
                      material = lancer.material{kd = 0, emission = 8}})
  return s
end

local function median(list)
  local t = {}
  for i, v in ipairs(list) do t[i] = v end
  table.sort(t)
  return t[(#t + 1) // 2]
end

-- ctx: {say, quick}. Returns the Markdown section.
function M.section(ctx)
  local say = ctx.say
  local W, H = 96, 72
  local runs = ctx.quick and 1 or 3
  local s = M.scene()
  local base = {width = W, height = H, light_samples = 1, progress = false}
  local function with(t)
    local o = {}
    for k, v in pairs(base) do o[k] = v end
    for k, v in pairs(t) do o[k] = v end
    return o
  end
  say("  reference: %dx%d at 4096 samples per pixel", W, H)
  local ref = s:render(with{samples = 4096, seed = 99})
  local ut, at, uni, ust, ada, ast = {}, {}
  for i = 1, runs do
    uni, ust = s:render(with{samples = 256})
    ut[i] = ust.trace_seconds
    ada, ast = s:render(with{samples = M.MAX, noise = M.NOISE, min_samples = 16})
    at[i] = ast.trace_seconds
    say("  run %d: uniform 256 %.3f s, adaptive %.3f s", i, ut[i], at[i])
  end
  local ue, ae = uni:error(ref), ada:error(ref)
  local ratio = median(at) / median(ut)
  local ok = ratio <= 0.5 and ae.rmse <= ue.rmse and math.abs(ae.bias) <= 0.5 / 255 and
             ast.converged >= 0.95 * W * H
  local lines = {"## Adaptive sampling (T7)\n\n",
    ("The T7 scene (80 %% flat sky, a glossy sphere, a soft shadow) at %dx%d, one\n"):format(W, H),
    "light and one cone sample per hit, against a 4096-spp reference; trace seconds,\n",
    ("median of %d interleaved run%s. Adaptive: `noise = %g, min_samples = 16, samples = %d`.\n"):format(
      runs, runs == 1 and "" or "s", M.NOISE, M.MAX),
    "Target: the adaptive render's RMSE at most uniform 256's in at most 0.5x its\n",
    "time, mean bias within 0.5/255, >= 95 % of pixels converged.\n\n",
    "| render | trace (s) | camera samples | RMSE | mean bias | pixels converged |\n",
    "| --- | --- | --- | --- | --- | --- |\n",
    ("| uniform 256 spp | %.3f | %d | %.5f | %+.2e | - |\n"):format(median(ut), ust.samples,
      ue.rmse, ue.bias),
    ("| adaptive | %.3f | %d | %.5f | %+.2e | %.1f %% |\n"):format(median(at), ast.samples,
      ae.rmse, ae.bias, 100 * ast.converged / (W * H)),
    ("\nTime ratio adaptive / uniform: %.2fx (%s).\n"):format(ratio, ok and "PASS" or "MISS")}
  return table.concat(lines)
end

return M
