-- mesh:add_faces holds the mesh's pointer while it reads the list; a list
-- whose __index closes the mesh makes it count a freed mesh's faces
-- (heap-use-after-free in lc_mesh_face_count).
local lancer = require "lancer"
local m = lancer.mesh{vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}}
local faces = setmetatable({}, {__len = function() return 3 end, __index = function(_, i)
  getmetatable(m).__close(m)
  return i
end})
m:add_faces(faces)
