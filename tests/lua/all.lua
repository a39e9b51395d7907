-- all.lua: runs every tests/lua/test_*.lua (or those named on the command
-- line) and ends with the line "N passed, M failed".
local T = require "harness"

local files = {...}
if #files == 0 then
  local p = assert(io.popen("ls tests/lua/test_*.lua"))
  for line in p:lines() do files[#files + 1] = line end
  p:close()
end
for _, f in ipairs(files) do dofile(f) end

local passed, failed, skipped = 0, 0, {}
for _, c in ipairs(T.cases) do
  local t0 = os.clock()
  local ok, err = xpcall(c.fn, debug.traceback)
  if ok then
    passed = passed + 1
    io.write(("ok   %s: %s (%.2fs)\n"):format(c.file, c.name, os.clock() - t0))
  elseif type(err) == "table" and err.skip then   -- T.skip: neither passed nor failed
    skipped[#skipped + 1] = ("%s: %s (%s)"):format(c.file, c.name, err.skip)
    io.write(("SKIP %s\n"):format(skipped[#skipped]))
  else
    failed = failed + 1
    io.write(("FAIL %s: %s\n  %s\n"):format(c.file, c.name, tostring(err):gsub("\n", "\n  ")))
  end
  io.flush()
end
if #skipped > 0 then
  io.write(("%d SKIPPED, not counted as passed:\n  %s\n"):format(#skipped,
    table.concat(skipped, "\n  ")))
end
io.write(("%d passed, %d failed\n"):format(passed, failed))
os.exit(failed == 0 and 0 or 1)
