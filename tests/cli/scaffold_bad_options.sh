#!/usr/bin/env bash
# cmcsurf scaffold: bad input exits 2, names the option, and writes nothing (no member is
# computed either: the cache stays empty).
source "$(dirname "$0")/usage.bash"
s=(scaffold --grid 16 --cache "$work/cache")
check_usage a.stl --porosity "${s[@]}" --porosity 1.5
check_usage b.stl --porosity "${s[@]}" --porosity 0
check_usage c.stl --solid "${s[@]}" --porosity 0.7 --solid surface
check_usage d.stl --size "${s[@]}" --porosity 0.7 --size 0x1x1
check_usage e.stl --size "${s[@]}" --porosity 0.7 --size 2x2
check_usage f.stl --cell-size "${s[@]}" --porosity 0.7 --cell-size -1
check_usage g.stl --units "${s[@]}" --porosity 0.7 --units furlong
check_usage h.xyz --format "${s[@]}" --porosity 0.7
check_usage i.stl --grid "${s[@]}" --porosity 0.7 --grid 13
check_usage j.stl --tolerance "${s[@]}" --porosity 0.7 --tolerance -1
check_usage k.stl --surface "${s[@]}" --porosity 0.7 --surface nosuch
check_usage l.stl --size "${s[@]}" --porosity 0.7 --size 1000
check_usage m.stl --shape "${s[@]}" --porosity 0.8:0.6 --solid sheet --shape "$work/nosuch.stl"
check_usage n.stl --porosity "${s[@]}" --porosity 0.8:0.8
check_usage o.stl --axis "${s[@]}" --porosity 0.8:0.6 --axis w
check_usage p.stl --graded-members "${s[@]}" --porosity 0.8:0.6 --graded-members 1
check_usage p2.stl --graded-members "${s[@]}" --porosity 0.8:0.6 --graded-members 3 --solid sheet
check_usage q.stl --compare-nodal "${s[@]}" --porosity 0.8:0.6 --compare-nodal
check_usage r.stl --skin "${s[@]}" --porosity 0.7 --skin 0.2
check_usage s.stl --shape "${s[@]}" --porosity 0.7 --shape "$work/nosuch.stl"
printf '%s\n' 'solid x' ' facet normal 0 0 1' '  outer loop' '   vertex 0 0 0' '   vertex 1 0 0' \
  '   vertex 0 1 0' '  endloop' ' endfacet' 'endsolid x' >"$work/open.stl"
check_usage t.stl --shape "${s[@]}" --porosity 0.7 --shape "$work/open.stl"
check_usage u.stl --size "${s[@]}" --porosity 0.7 --shape "$work/open.stl" --size 4
# A part whose mesh would not fit the memory (a 1 GB address space here): refused before the
# member is computed (the default 10 mm box at --grid 128 is 640^3 lattice nodes).
under_memory_limit v.stl --size scaffold --grid 128 --cache "$work/cache" --porosity 0.7 \
  --size 10
if [ -e "$work/cache" ]; then echo "FAIL: a member was computed for bad input"; fail=1; fi
[ "$fail" -eq 0 ] && echo "scaffold_bad_options: all passed"
exit "$fail"
