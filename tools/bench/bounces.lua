-- bounces.lua: what each bounce of `indirect` costs and buys, on the Cornell
-- box (scenes/cornell.lua): for indirect = 0, 1, 2, 3, 4, 6, 8, 16 at a fixed
-- number of samples, the trace time, the rays per camera sample, the mean
-- (the truncation shows as a bias) and the RMSE against a converged
-- reference (indirect = 64, 16 times the samples, averaged over two seeds).
--   build/bin/lancer tools/bench/bounces.lua [side = 64] [samples = 64]
local side = tonumber(arg and arg[1]) or 64
local samples = tonumber(arg and arg[2]) or 64
local scene = assert(loadfile("scenes/cornell.lua"))("--scene")

local function mean(img)
  local s = 0
  for y = 1, img.height do
    for x = 1, img.width do
      local r, g, b = img:pixel(x, y)
      s = s + (r + g + b) / 3
    end
  end
  return s / (img.width * img.height)
end

local o = {width = side, height = side, samples = samples * 8, indirect = 64, seed = 1001}
local ref = scene:render(o)
o.seed = 1002
ref:add((scene:render(o))):add(ref, -0.5)    -- (a + b) / 2

print(("reference: %dx%d, indirect 64, 2 x %d samples; mean %.5f"):format(side, side,
      samples * 8, mean(ref)))
print(("%8s %9s %12s %9s %9s %9s"):format("indirect", "seconds", "rays/sample", "mean",
      "bias", "RMSE"))
local last
for _, n in ipairs{0, 1, 2, 3, 4, 6, 8, 16} do
  local img, st = scene:render{width = side, height = side, samples = samples, indirect = n,
                               seed = 7}
  local rays = 0
  for k, v in pairs(st.rays) do if k ~= "cut" then rays = rays + v end end
  local e = img:error(ref)
  print(("%8d %9.3f %12.2f %9.5f %9.5f %9.5f"):format(n, st.trace_seconds,
        rays / st.samples, mean(img), e.bias, e.rmse))
end
