-- run.lua: runs one command under lc-runstat and reads back what it measured.
--
-- Every renderer is run the same way: `cd dir && lc-runstat cmd... > log 2>&1`.
-- lc-runstat's last line gives wall time, peak RSS and exit status; lancer's
-- bench scripts add one "bench <scene> key=value ..." line of their own.
local R = {}

-- A word for sh, in single quotes.
function R.quote(word)
  return "'" .. tostring(word):gsub("'", [['\'']]) .. "'"
end

-- True when program is on PATH.
function R.available(program)
  return os.execute("command -v " .. R.quote(program) .. " > /dev/null 2>&1") == true
end

-- The first line a shell command prints, or nil.
function R.output(command)
  local p = io.popen(command .. " 2> /dev/null")
  if not p then return nil end
  local line = p:read("l")
  p:close()
  return line
end

local function read_file(path)
  local f = io.open(path, "rb")
  if not f then return "" end
  local text = f:read("a")
  f:close()
  return text
end

-- Runs argv (a list of words) from directory dir through the runstat
-- binary, all output to log. Returns a table:
--   wall (s), rss_mb, status, bench = {key = number, ...} (lancer's line),
--   log = the whole output (for the peers' own timings).
-- wall is nil when no runstat line came back (runstat itself missing).
function R.measure(runstat, argv, dir, log)
  local words = {}
  for i, w in ipairs(argv) do words[i] = R.quote(w) end
  os.execute(("cd %s && %s %s > %s 2>&1"):format(R.quote(dir), R.quote(runstat),
                                                 table.concat(words, " "), R.quote(log)))
  local text = read_file(log)
  local result = {log = text, bench = {}}
  local pattern = "runstat wall=([%d.]+) maxrss_kb=(%d+) status=(%d+)"
  for wall, kb, status in text:gmatch(pattern) do      -- the last one is the run's
    result.wall, result.rss_mb, result.status = tonumber(wall), tonumber(kb) / 1024,
                                                tonumber(status)
  end
  local line = text:match("\nbench [^\n]*") or text:match("^bench [^\n]*")
  if line then
    for key, value in line:gmatch("(%w+)=([-%d.e+]+)") do
      result.bench[key] = tonumber(value)
    end
  end
  return result
end

-- The last few lines of a log, to show why a run failed.
function R.tail(text, n)
  local lines = {}
  for line in text:gmatch("[^\r\n]+") do
    lines[#lines + 1] = line
    if #lines > n then table.remove(lines, 1) end
  end
  return table.concat(lines, "\n")
end

-- The median of a list of numbers (nil for an empty list).
function R.median(list)
  if #list == 0 then return nil end
  local s = {}
  for i, v in ipairs(list) do s[i] = v end
  table.sort(s)
  local m = (#s + 1) // 2
  return #s % 2 == 1 and s[m] or (s[m] + s[m + 1]) / 2
end

return R
