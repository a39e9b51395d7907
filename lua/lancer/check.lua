-- lancer.check: `lancer --check SCRIPT.lua`. Each render the script asks
-- for is done small, then again with the whole scene scaled by 1e-3 and
-- 1e3 and moved 1e6 away; an exact renderer draws the same picture every
-- time. The report gives, per variant, the share of pixels within 1/255 of
-- the original, NaN or infinite channels, and reflection rays that hit the
-- surface they left. A scene is unstable when any variant has fewer than
-- 99.9 % of pixels within 1/255, or any NaN, infinity or self-hit.
local M = {renders = 0, unstable = 0}

local SIDE = 128            -- the longest side of the check renders
local WITHIN = 0.999        -- docs/numerics.md's H1/H2 threshold
local VARIANTS = {
  {"scale 1e-3", 1e-3},
  {"scale 1e3", 1e3},
  {"moved by 1e6", 1, {1e6, 1e6 / 2, 1e6 / 3}},
}

local function line(fmt, ...) io.stderr:write(fmt:format(...), "\n") end

-- Renders `scene` with the script's options made small, through plain (the
-- render without the host hook).
local function small(plain, scene, opts)
  local o = {}
  for k, v in pairs(opts or {}) do o[k] = v end
  local w, h = o.width or 640, o.height or 480
  local k = math.min(1, SIDE / math.max(w, h))
  o.width, o.height = math.max(1, math.floor(w * k + 0.5)), math.max(1, math.floor(h * k + 0.5))
  o.progress = false
  return plain(scene, o)
end

-- Called by the lancer command's host hook (lancer.host) in place of the
-- render the script asked for; plain renders without the hook.
function M.render(scene, opts, plain)
  local ref, st = small(plain, scene, opts)
  M.renders = M.renders + 1
  line("check: render %d at %dx%d: %d NaN or infinite channels, %d self-hits",
       M.renders, ref.width, ref.height, ref:nonfinite(), st.self_hits)
  local bad = ref:nonfinite() > 0 or st.self_hits > 0
  for _, v in ipairs(VARIANTS) do
    local built, img, vst = pcall(function()
      return small(plain, scene:transformed(v[2], v[3]), opts)
    end)
    if not built then     -- beyond double's range: as unstable as can be
      line("  %-13s cannot be rendered: %s  UNSTABLE", v[1], tostring(img):gsub("^.-: ", ""))
      bad = true
      goto next
    end
    local d = img:diff(ref, 1 / 255)
    local fail = d.within < WITHIN or img:nonfinite() > 0 or vst.self_hits > 0
    line("  %-13s %7.3f %% of pixels within 1/255 (worst %.3g at %d,%d), %d NaN/inf, %d self-hits%s",
         v[1], 100 * d.within, d.max, d.worst_x, d.worst_y, img:nonfinite(), vst.self_hits,
         fail and "  UNSTABLE" or "")
    bad = bad or fail
    ::next::
  end
  if bad then M.unstable = M.unstable + 1 end
  return ref, st
end

-- After the script: a summary, and whether every render was stable.
function M.finish()
  if M.renders == 0 then
    line("check: the script rendered nothing")
    return false
  end
  line("check: %d of %d renders unstable", M.unstable, M.renders)
  return M.unstable == 0
end

return M
