-- lancer: the module people require. The C core's functions are exported
-- as they are (so errors point at the caller's line); pure-Lua helpers that
-- need no speed live here beside them.
local core = require "lancer.core"

local M = {}
for k, v in pairs(core) do M[k] = v end
-- A traceback names a C function after the first loaded module holding it,
-- and package.loaded's order changes from run to run: with the functions in
-- both lancer and lancer.core, one error read 'lancer.sphere' in one run
-- and 'lancer.core.sphere' in the next. They live here alone, the name
-- people call; lancer.core is left a view of this module.
for k in pairs(M) do core[k] = nil end
setmetatable(core, {__index = M})

-- Interpolation for animations (lua/lancer/motion.lua): lancer.lerp,
-- lancer.smoothstep, lancer.ease.in_out_cubic, lancer.keyframes{...}, ...
M.motion = require "lancer.motion"
for _, k in ipairs{"lerp", "smoothstep", "ease", "keyframes", "lerp_angle"} do
  M[k] = M.motion[k]
end

-- lancer.ledger(stats): the statistics of a render as a readable table.
M.ledger = require("lancer.ledger").format

-- lancer.animate{frames, fps, output, render, frame = function(f) ... end}
M.animate = require("lancer.anim").animate

return M
