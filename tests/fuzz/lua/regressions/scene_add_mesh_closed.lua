-- scene:add, likewise for a mesh: lc_scene_add_mesh(NULL, ...) (add_mesh).
local lancer = require "lancer"
local s = lancer.scene{}
local tri = lancer.triangle{a = {0, 0, 0}, b = {1, 0, 0}, c = {0, 1, 0}}
s:add(lancer.sphere{center = {0, 2, 0}, radius = 1})   -- the default material is in
local list = setmetatable({}, {__len = function() getmetatable(s).__close(s); return 0 end})
s:add(tri, list)
