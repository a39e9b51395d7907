-- lancer: the module people require. The C core's functions are exported
-- as they are (so errors point at the caller's line); pure-Lua helpers that
-- need no speed live here beside them.
local core = require "lancer.core"

local M = {}

-- A traceback names a function after the first module in package.loaded
-- whose field holds it, and that table's order changes from run to run:
-- with sphere in both lancer and lancer.core (lerp in lancer and
-- lancer.motion, ...), one error read 'lancer.sphere' in one run and
-- 'lancer.core.sphere' in the next. So what this module exports lives in
-- it alone, under the name people call; the module it comes from keeps
-- it behind __index, so require "lancer.core".sphere still answers.
-- names maps each name here to the name in mod.
local function export(mod, names)
  local lent = {}
  for here, there in pairs(names) do
    M[here] = mod[there]
    if type(mod[there]) == "function" then lent[there], mod[there] = mod[there], nil end
  end
  setmetatable(mod, {__index = lent})
end

local all = {}
for k in pairs(core) do all[k] = k end
export(core, all)

-- Interpolation for animations (lua/lancer/motion.lua): lancer.lerp,
-- lancer.smoothstep, lancer.ease.in_out_cubic, lancer.keyframes{...}, ...
M.motion = require "lancer.motion"
export(M.motion, {lerp = "lerp", smoothstep = "smoothstep", ease = "ease",
                  keyframes = "keyframes", lerp_angle = "lerp_angle"})

-- lancer.ledger(stats): the statistics of a render as a readable table.
export(require "lancer.ledger", {ledger = "format"})

-- lancer.animate{frames, fps, output, render, frame = function(f) ... end}
export(require "lancer.anim", {animate = "animate"})

return M
