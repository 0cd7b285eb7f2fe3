#!/usr/bin/env bash
# The module graph as built, drawn from the CMake link lists (read by check-includes.sh --graph,
# the one parser of them). Usage: module-graph.sh --mermaid|--svg|--table [repo-root]
#   --mermaid: a mermaid flowchart, one arrow per dependency not implied by the others (the
#              transitive reduction; dotted: private entries);
#   --svg:     the same graph as an SVG drawing (layers: a module sits one row above the highest
#              module it depends on), written to stdout;
#   --table:   one Markdown table row per module with its direct public and private entries.
# docs/architecture.md shows the output; regenerate it with
#   scripts/module-graph.sh --mermaid; scripts/module-graph.sh --svg > docs/img/architecture.svg
set -euo pipefail
mode=${1:?usage: module-graph.sh --mermaid|--svg|--table [repo-root]}
root=${2:-$(cd "$(dirname "$0")/.." && pwd)}
graph=$(bash "$(dirname "$0")/check-includes.sh" --graph "$root")

awk -v mode="$mode" '
  # Input lines: "<module> public: a b ... private: c d ..."
  {
    m = $1; mods[m] = 1; order[++n] = m; kind = ""
    for (i = 2; i <= NF; i++) {
      if ($i == "public:") { kind = "public"; continue }
      if ($i == "private:") { kind = "private"; continue }
      dep[m, $i] = kind; deps[m] = deps[m] " " $i
      if (kind == "public") pub[m] = pub[m] " " $i
    }
  }
  # reach(a, b): b is reachable from a through public entries.
  function reach(a, b,    k, list, j) {
    if ((a, b) in memo) return memo[a, b]
    memo[a, b] = 0
    k = split(pub[a], list, " ")
    for (j = 1; j <= k; j++) if (list[j] == b || reach(list[j], b)) { memo[a, b] = 1; break }
    return memo[a, b]
  }
  function implied(a, b,    k, list, j) {  # a -> b implied by another entry of a
    k = split(deps[a], list, " ")
    for (j = 1; j <= k; j++) if (list[j] != b && reach(list[j], b)) return 1
    return 0
  }
  function depth(m,    k, list, j, d, best) {
    if (m in level) return level[m]
    best = 0; k = split(deps[m], list, " ")
    for (j = 1; j <= k; j++) { d = depth(list[j]) + 1; if (d > best) best = d }
    level[m] = best
    return best
  }
  function place(    d, j, x0) {
    for (d = 0; d <= top; d++) {
      x0 = (W - C[d] * (bw + gap) + gap) / 2
      for (j = 1; j <= C[d]; j++) { x[R[d, j]] = x0 + (j - 1) * (bw + gap) + bw / 2; y[R[d, j]] = H - 20 - d * dy - bh / 2 }
    }
  }
  function sort_row(d, nb,    j, k, q, s, t, key, nl, a, b, tk, tn) {
    for (j = 1; j <= C[d]; j++) {
      s = 0; t = 0; k = split(nb[R[d, j]], nl, " ")
      for (q = 1; q <= k; q++) { s += x[nl[q]]; t++ }
      key[j] = (t ? s / t : x[R[d, j]]) + j * 1e-6
    }
    for (a = 1; a <= C[d]; a++) for (b = a + 1; b <= C[d]; b++) if (key[b] < key[a]) {
      tk = key[a]; key[a] = key[b]; key[b] = tk; tn = R[d, a]; R[d, a] = R[d, b]; R[d, b] = tn
    }
    place()
  }
  END {
    if (mode == "--table") {
      for (i = 1; i <= n; i++) {
        m = order[i]; p = ""; q = ""
        k = split(deps[m], list, " ")
        for (j = 1; j <= k; j++) {
          if (dep[m, list[j]] == "public") p = p (p == "" ? "" : ", ") list[j]
          else q = q (q == "" ? "" : ", ") list[j]
        }
        printf "| `%s` | %s | %s |\n", m, (p == "" ? "-" : p), (q == "" ? "-" : q)
      }
      exit
    }
    if (mode == "--mermaid") {
      print "flowchart BT"
      for (i = 1; i <= n; i++) {
        m = order[i]; k = split(deps[m], list, " ")
        for (j = 1; j <= k; j++) {
          if (implied(m, list[j])) continue
          printf "  %s %s %s\n", m, (dep[m, list[j]] == "public" ? "-->" : "-.->"), list[j]
        }
      }
      exit
    }
    if (mode != "--svg") { print "module-graph.sh: unknown option " mode > "/dev/stderr"; exit 2 }
    top = 0
    for (i = 1; i <= n; i++) { d = depth(order[i]); row[d] = row[d] " " order[i]; if (d > top) top = d }
    # Rows from the bottom (core); inside a row, the order of the mean position of the
    # neighbours (barycentre sweeps up through the dependencies, down through the dependents).
    bw = 104; bh = 30; gap = 22; dy = 78; widest = 0
    for (d = 0; d <= top; d++) {
      C[d] = split(row[d], list, " ")
      for (j = 1; j <= C[d]; j++) R[d, j] = list[j]
      if (C[d] > widest) widest = C[d]
    }
    W = widest * (bw + gap) + gap; H = (top + 1) * dy + 20
    for (i = 1; i <= n; i++) {
      m = order[i]; k = split(deps[m], list, " ")
      for (j = 1; j <= k; j++) if (!implied(m, list[j])) { up[list[j]] = up[list[j]] " " m; down[m] = down[m] " " list[j] }
    }
    place()
    for (sweep = 1; sweep <= 6; sweep++) {
      for (d = 1; d <= top; d++) sort_row(d, down)
      for (d = top - 1; d >= 0; d--) sort_row(d, up)
    }
    printf "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" viewBox=\"0 0 %d %d\" font-family=\"sans-serif\" font-size=\"13\">\n", W, H, W, H
    print "<title>MANTA modules and their link dependencies (src/*/CMakeLists.txt)</title>"
    print "<defs><marker id=\"a\" viewBox=\"0 0 10 10\" refX=\"10\" refY=\"5\" markerWidth=\"7\" markerHeight=\"7\" orient=\"auto\"><path d=\"M0,0 L10,5 L0,10 z\" fill=\"#555\"/></marker></defs>"
    print "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>"
    for (i = 1; i <= n; i++) {
      m = order[i]; k = split(deps[m], list, " ")
      for (j = 1; j <= k; j++) {
        b = list[j]; if (implied(m, b)) continue
        x1 = x[m]; y1 = y[m] + bh / 2; x2 = x[b]; y2 = y[b] - bh / 2
        printf "<path d=\"M%.1f,%.1f C%.1f,%.1f %.1f,%.1f %.1f,%.1f\" fill=\"none\" stroke=\"#555\" stroke-width=\"1.2\"%s marker-end=\"url(#a)\"/>\n", x1, y1, x1, y1 + 35, x2, y2 - 35, x2, y2, (dep[m, b] == "public" ? "" : " stroke-dasharray=\"4 3\"")
      }
    }
    for (i = 1; i <= n; i++) {
      m = order[i]
      printf "<rect x=\"%.1f\" y=\"%.1f\" width=\"%d\" height=\"%d\" rx=\"5\" fill=\"#eef3fb\" stroke=\"#1f4e96\"/>\n", x[m] - bw / 2, y[m] - bh / 2, bw, bh
      printf "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">%s</text>\n", x[m], y[m] + 4.5, m
    }
    print "</svg>"
  }' <<<"$graph"
