-- A list whose element is a sphere while scene:add checks it and the list
-- itself once it adds it: check_addable stops at depth 64, add_one recurses
-- without bound and overflows the C stack.
local lancer = require "lancer"
local s = lancer.scene{}
local ball = lancer.sphere{center = {0, 0, 0}, radius = 1}
local reads = 0
local list
list = setmetatable({}, {__len = function() return 1 end,
                         __index = function() reads = reads + 1
                                              return reads > 1 and list or ball end})
s:add(list)
