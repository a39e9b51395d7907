-- mesh:add_vertices, likewise (heap-use-after-free in lc_mesh_vertex_count).
local lancer = require "lancer"
local m = lancer.mesh{}
local points = setmetatable({}, {__len = function() return 3 end, __index = function(_, i)
  getmetatable(m).__close(m)
  return i
end})
m:add_vertices(points)
