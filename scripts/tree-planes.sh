# tree-planes.sh: the splitter tree's planes (thesis chapter 6.3), sourced by render.sh
# and bench-pipeline.sh so that both build the same tree.
#
# tree_planes WIDTH HEIGHT DEPTH sets plane_of[NODE] for nodes 1 .. 2^DEPTH − 1, numbered
# as a heap: node 1 is the root, the children of node i are 2i (out1: x_s ≤ K or
# y_s ≤ K) and 2i+1 (the rest); leaves are nodes 2^DEPTH .. 2^(DEPTH+1) − 1. Levels
# alternate x and y planes, starting with x.
#
# Each node's region is a rectangle of whole pixels, columns x0..x1 and rows y0..y1
# (half-open), and it is bisected on a pixel BOUNDARY: column c = (x0 + x1)/2 is the plane
# x_s = 2c/W − 1, row r the plane y_s = 1 − 2r/H. A cut then never passes through a pixel
# centre (centres are at half-integers), so the new edges along it decide no centre that
# the whole polygon would not have; with the edge supports and the recorded plane, a tree
# of any depth renders byte for byte as depth 0. K is printed with 17 significant digits
# so that it reads back as the double awk computed (and 0 as 0, not -0).

# k_of N D SIGN: SIGN·(2N/D − 1).
k_of() {
    awk -v n="$1" -v d="$2" -v s="$3" \
        'BEGIN { k = s * (2 * n / d - 1); if (k == 0) k = 0; printf "%.17g", k }'
}

tree_planes() {
    local width=$1 height=$2 depth=$3
    local leaves=$((1 << depth)) node level n a b m
    local -A x0 x1 y0 y1
    declare -gA plane_of=()
    x0[1]=0 x1[1]=$width y0[1]=0 y1[1]=$height
    for ((node = 1; node < leaves; node++)); do
        level=0
        for ((n = node; n > 1; n /= 2)); do level=$((level + 1)); done
        a=$((2 * node)) b=$((2 * node + 1))
        x0[$a]=${x0[$node]} x1[$a]=${x1[$node]} y0[$a]=${y0[$node]} y1[$a]=${y1[$node]}
        x0[$b]=${x0[$node]} x1[$b]=${x1[$node]} y0[$b]=${y0[$node]} y1[$b]=${y1[$node]}
        if ((level % 2 == 0)); then
            m=$(((x0[$node] + x1[$node]) / 2))
            plane_of[$node]="x=$(k_of "$m" "$width" 1)"
            x1[$a]=$m x0[$b]=$m
        else
            # y_s ≤ K is Y ≥ r: out1 gets the rows below the boundary.
            m=$(((y0[$node] + y1[$node]) / 2))
            plane_of[$node]="y=$(k_of "$m" "$height" -1)"
            y0[$a]=$m y1[$b]=$m
        fi
    done
}
