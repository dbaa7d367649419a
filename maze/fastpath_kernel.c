/* The inner loops of mazelog's fastest-path query (maze/fastpath_query.py and maze/fastpath_bound.py say what
 * each step is for), compiled at first use by maze/fastpath_kernel.py and called through ctypes.
 *
 * Every step computes exactly what the scipy path computes, so that routes stay identical to the bit: Dijkstra's
 * times are the minimum over paths of the left-to-right sums dist[u] + w (whatever order nodes are settled in),
 * a limit keeps the nodes whose time is <= the limit (scipy's rule), and ties are broken by the rules written
 * in maze/fastpath_query.py (the lowest-numbered goal node, the earliest then highest-numbered predecessor).
 * It must be compiled without contracting a * b + c into one rounding (-ffp-contract=off).
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    double key;
    int32_t node;
} item;

/* The working memory of one query graph of n nodes and m edges, kept between its queries: the time arrays are
 * all infinite and the flags all clear between calls (each call resets only what it touched). */
typedef struct {
    int32_t n;
    int64_t m;
    double *reduced;  /* A*'s times (reduced prices) */
    double *exact;    /* the exact search's times, local numbering */
    uint8_t *done;
    uint8_t *kept;
    item *heap;
    int32_t *touched;
    int32_t *local;   /* node -> its number among the kept nodes */
    int32_t *nodes;   /* the kept nodes, ascending */
    int32_t *lrow, *lcol, *ledge, *lindptr, *rindptr, *rsrc, *queue, *pred;
    int32_t *slot;    /* where each node is in the heap, -1 for nowhere (between searches: everywhere -1) */
    double *lprice;
    int32_t walls;          /* pricing (fp_price): 0 before the first query */
    uint8_t *open_wall;     /* per wall id and the two sentinels, the last query's: whether it is open */
    uint8_t *was_open;
    int32_t *wall_indptr;   /* the edges that need wall w open: wall_edges[wall_indptr[w]:wall_indptr[w + 1]] */
    int32_t *wall_edges;
} workspace;

/* A 4-ary heap of nodes keyed by their tentative times, each node in it at most once (`slot`: where it is, -1
 * for nowhere), so that lowering a node's time moves it rather than adding a second entry. */
static void place(workspace *ws, int64_t i, item it) {
    while (i > 0) {
        int64_t parent = (i - 1) / 4;
        if (ws->heap[parent].key <= it.key) break;
        ws->heap[i] = ws->heap[parent];
        ws->slot[ws->heap[i].node] = (int32_t)i;
        i = parent;
    }
    ws->heap[i] = it;
    ws->slot[it.node] = (int32_t)i;
}

static void push(workspace *ws, int64_t *size, double key, int32_t node) {
    int64_t i = ws->slot[node];
    place(ws, i < 0 ? (*size)++ : i, (item){key, node});
}

static item pop(workspace *ws, int64_t *size) {
    item *heap = ws->heap, top = heap[0], last = heap[--(*size)];
    ws->slot[top.node] = -1;
    int64_t i = 0, n = *size;
    if (!n) return top;
    for (;;) {
        int64_t c = 4 * i + 1, best = c;
        if (c >= n) break;
        for (int64_t k = c + 1; k < c + 4 && k < n; k++)
            if (heap[k].key < heap[best].key) best = k;
        if (heap[best].key >= last.key) break;
        heap[i] = heap[best];
        ws->slot[heap[i].node] = (int32_t)i;
        i = best;
    }
    heap[i] = last;
    ws->slot[last.node] = (int32_t)i;
    return top;
}

/* Dijkstra from `sources` (time 0) over CSR rows (indptr, indices), the weight of entry j being
 * w[edge_of ? edge_of[j] : j], or infinite where mask says the edge is closed. Times go to dist (infinite on
 * entry); nodes given a time are appended to touched. Returns how many nodes it settled (their times are
 * finite and <= limit). */
static int32_t dijkstra(const int32_t *indptr, const int32_t *indices, const double *w, const int32_t *edge_of,
                        const uint8_t *mask, const int32_t *sources, int32_t nsrc, double limit, double *dist,
                        workspace *ws, int32_t *ntouched) {
    int64_t size = 0;
    int32_t settled = 0;
    for (int32_t s = 0; s < nsrc; s++) {
        if (dist[sources[s]] == INFINITY) ws->touched[(*ntouched)++] = sources[s];
        dist[sources[s]] = 0.0;
        push(ws, &size, 0.0, sources[s]);
    }
    while (size) {
        item it = pop(ws, &size);
        int32_t v = it.node;
        ws->done[v] = 1;
        settled++;
        double at = dist[v];
        for (int32_t j = indptr[v]; j < indptr[v + 1]; j++) {
            int32_t u = indices[j];
            if (ws->done[u]) continue;
            int32_t e = edge_of ? edge_of[j] : j;
            if (mask && !mask[e]) continue;
            double next = at + w[e];
            if (next <= limit && next < dist[u]) {
                if (dist[u] == INFINITY) ws->touched[(*ntouched)++] = u;
                dist[u] = next;
                push(ws, &size, next, u);
            }
        }
    }
    return settled;
}

static void clear(double *dist, workspace *ws, int32_t ntouched) {
    for (int32_t i = 0; i < ntouched; i++) {
        dist[ws->touched[i]] = INFINITY;
        ws->done[ws->touched[i]] = 0;
    }
}

void *fp_new(int32_t n, int64_t m) {
    workspace *ws = calloc(1, sizeof *ws);
    if (!ws) return NULL;
    ws->n = n;
    ws->m = m;
    ws->reduced = malloc(sizeof(double) * n);
    ws->exact = malloc(sizeof(double) * n);
    ws->done = calloc(n, 1);
    ws->kept = calloc(n + 1, 1);
    ws->heap = malloc(sizeof(item) * (n + 1));
    ws->slot = malloc(sizeof(int32_t) * (n + 1));
    ws->touched = malloc(sizeof(int32_t) * (n + 1));
    ws->local = malloc(sizeof(int32_t) * n);
    ws->nodes = malloc(sizeof(int32_t) * n);
    ws->lrow = malloc(sizeof(int32_t) * (m + n + 1));
    ws->lcol = malloc(sizeof(int32_t) * (m + n + 1));
    ws->ledge = malloc(sizeof(int32_t) * (m + 1));
    ws->lindptr = malloc(sizeof(int32_t) * (n + 2));
    ws->rindptr = malloc(sizeof(int32_t) * (n + 3));
    ws->rsrc = malloc(sizeof(int32_t) * (m + n + 1));
    ws->queue = malloc(sizeof(int32_t) * (n + 1));
    ws->pred = malloc(sizeof(int32_t) * n);
    ws->lprice = malloc(sizeof(double) * (m + 1));
    if (!ws->reduced || !ws->exact || !ws->done || !ws->kept || !ws->heap || !ws->slot || !ws->touched || !ws->local
        || !ws->nodes || !ws->lrow || !ws->lcol || !ws->ledge || !ws->lindptr || !ws->rindptr || !ws->rsrc
        || !ws->queue || !ws->pred || !ws->lprice) {
        return NULL;  /* the caller falls back; what was allocated is lost once, at start-up */
    }
    for (int32_t i = 0; i < n; i++) ws->reduced[i] = ws->exact[i] = INFINITY, ws->slot[i] = -1;
    return ws;
}

void fp_free(void *p) {
    workspace *ws = p;
    if (!ws) return;
    free(ws->reduced); free(ws->exact); free(ws->done); free(ws->kept); free(ws->heap); free(ws->slot); free(ws->touched);
    free(ws->local); free(ws->nodes); free(ws->lrow); free(ws->lcol); free(ws->ledge); free(ws->lindptr);
    free(ws->rindptr); free(ws->rsrc); free(ws->queue); free(ws->pred); free(ws->lprice);
    free(ws->open_wall); free(ws->was_open); free(ws->wall_indptr); free(ws->wall_edges);
    free(ws);
}

/* TimeBound.find: the exact times to the goal (`times`, every node) by one search back from the goal nodes over
 * the reversed graph (rindptr, rindices, redge: the forward edge of each reversed entry) through the open edges,
 * and the reduced prices of the forward edges (rows, indices) under them. Returns the nodes it reached. */
int32_t fp_bound(void *p, const int32_t *rindptr, const int32_t *rindices, const int32_t *redge,
                 const int32_t *rows, const int32_t *indices, const double *price, const uint8_t *open,
                 const int32_t *goals, int32_t ngoals, double *times, double *reduced) {
    workspace *ws = p;
    int32_t ntouched = 0;
    for (int32_t i = 0; i < ws->n; i++) times[i] = INFINITY;
    int32_t cost = dijkstra(rindptr, rindices, price, redge, open, goals, ngoals, INFINITY, times, ws, &ntouched);
    for (int32_t i = 0; i < ntouched; i++) ws->done[ws->touched[i]] = 0;
    for (int64_t e = 0; e < ws->m; e++) {
        double r = (price[e] + times[indices[e]]) - times[rows[e]];
        reduced[e] = isnan(r) ? INFINITY : (r < 0.0 ? 0.0 : r);  /* numpy: maximum(r, 0), NaN -> inf */
    }
    return cost;
}

static double with_slack(double seconds, double slack) { return seconds + slack * (1 + seconds); }

static int cmp_int32(const void *a, const void *b) {
    int32_t x = *(const int32_t *)a, y = *(const int32_t *)b;
    return (x > y) - (x < y);
}

/* FastestSearch.search: A* from the start (the last node) on the reduced prices `astar` of the open edges under limits
 * limit0 * growth^k (k < tries, then none), adding the nodes each try settles to *spent; then the exact search
 * of the nodes that could lie on a fastest route (narrowed to those the goal is reached from by tight edges when
 * more than narrow_from are kept) on the prices, limited to the fastest time plus the bound at the start; and
 * the route walked back from the goal. Writes the route's nodes (start first) and their times, sets *hint to
 * A*'s reduced time to the goal, and returns the route's node count; 0 when the goal cannot be reached. */
int32_t fp_search(void *p, const int32_t *indptr, const int32_t *indices, const double *astar, const double *price,
                  const uint8_t *open, int32_t goal_lo, int32_t goal_hi, double limit0, double growth,
                  int32_t tries, double at_start, double slack, int32_t narrow_from, int64_t *spent, double *hint,
                  int32_t *route, double *times) {
    workspace *ws = p;
    int32_t n = ws->n, start = n - 1, ntouched = 0, best = -1;
    double *reduced = ws->reduced;
    for (int32_t k = 0; k <= tries; k++) {
        double limit = k < tries ? limit0 * pow(growth, k) : INFINITY;
        clear(reduced, ws, ntouched);
        ntouched = 0;
        *spent += dijkstra(indptr, indices, astar, NULL, open, &start, 1, limit, reduced, ws, &ntouched);
        best = goal_lo;
        for (int32_t g = goal_lo + 1; g < goal_hi; g++)
            if (reduced[g] < reduced[best]) best = g;
        if (goal_lo < goal_hi && reduced[best] < INFINITY) break;
        best = -1;
    }
    if (best < 0) {
        clear(reduced, ws, ntouched);
        return 0;
    }
    double fastest = reduced[best];
    *hint = fastest;
    double keep_to = with_slack(fastest, slack);

    /* the kept nodes, ascending, and the open edges between them, in row order */
    int32_t count = 0;
    for (int32_t i = 0; i < ntouched; i++)
        if (reduced[ws->touched[i]] <= keep_to) ws->nodes[count++] = ws->touched[i];
    qsort(ws->nodes, count, sizeof(int32_t), cmp_int32);
    for (int32_t i = 0; i < count; i++) {
        ws->kept[ws->nodes[i]] = 1;
        ws->local[ws->nodes[i]] = i;
    }
    int64_t edges = 0;
    for (int32_t i = 0; i < count; i++) {
        int32_t v = ws->nodes[i];
        for (int32_t j = indptr[v]; j < indptr[v + 1]; j++) {
            if (!open[j] || !ws->kept[indices[j]]) continue;
            ws->lrow[edges] = i;
            ws->lcol[edges] = ws->local[indices[j]];
            ws->ledge[edges++] = j;
        }
    }
    for (int32_t i = 0; i < count; i++) ws->kept[ws->nodes[i]] = 0;

    if (count > narrow_from) {
        /* _on_fastest_routes: back from the goal (a node `count` joined to the kept goal nodes) over tight edges */
        double margin = keep_to - fastest;
        uint8_t *on = ws->kept;  /* clear again by the end */
        int32_t *rindptr = ws->rindptr, *rsrc = ws->rsrc;
        memset(rindptr, 0, sizeof(int32_t) * (count + 3));
        int64_t extra = 0;
        for (int64_t e = 0; e < edges; e++) {
            int32_t r = ws->lrow[e], c = ws->lcol[e];
            if (reduced[ws->nodes[r]] + astar[ws->ledge[e]] <= reduced[ws->nodes[c]] + margin) rindptr[c + 2]++;
        }
        for (int32_t i = 0; i < count; i++)
            if (ws->nodes[i] >= goal_lo && ws->nodes[i] < goal_hi) { rindptr[count + 2]++; extra++; }
        for (int32_t i = 0; i <= count; i++) rindptr[i + 2] += rindptr[i + 1];
        for (int64_t e = 0; e < edges; e++) {
            int32_t r = ws->lrow[e], c = ws->lcol[e];
            if (reduced[ws->nodes[r]] + astar[ws->ledge[e]] <= reduced[ws->nodes[c]] + margin)
                rsrc[rindptr[c + 1]++] = r;
        }
        for (int32_t i = 0; i < count; i++)
            if (ws->nodes[i] >= goal_lo && ws->nodes[i] < goal_hi) rsrc[rindptr[count + 1]++] = i;
        (void)extra;
        int32_t head = 0, tail = 0;
        ws->queue[tail++] = count;
        on[count] = 1;
        while (head < tail) {
            int32_t v = ws->queue[head++];
            for (int32_t j = rindptr[v]; j < rindptr[v + 1]; j++)
                if (!on[rsrc[j]]) { on[rsrc[j]] = 1; ws->queue[tail++] = rsrc[j]; }
        }
        int32_t *renumber = ws->local;  /* reused: kept index -> narrowed index */
        int32_t narrowed = 0;
        for (int32_t i = 0; i < count; i++) {
            renumber[i] = on[i] ? narrowed : -1;
            if (on[i]) ws->nodes[narrowed++] = ws->nodes[i];
        }
        int64_t used = 0;
        for (int64_t e = 0; e < edges; e++) {
            int32_t r = ws->lrow[e], c = ws->lcol[e];
            if (!on[r] || !on[c]) continue;
            ws->lrow[used] = renumber[r];
            ws->lcol[used] = renumber[c];
            ws->ledge[used++] = ws->ledge[e];
        }
        for (int32_t i = 0; i <= count; i++) on[i] = 0;
        count = narrowed;
        edges = used;
    }

    /* the exact search of the sub graph, from the start (its last node) */
    memset(ws->lindptr, 0, sizeof(int32_t) * (count + 1));
    for (int64_t e = 0; e < edges; e++) {
        ws->lindptr[ws->lrow[e] + 1]++;
        ws->lprice[e] = price[ws->ledge[e]];
    }
    for (int32_t i = 0; i < count; i++) ws->lindptr[i + 1] += ws->lindptr[i];
    clear(reduced, ws, ntouched);
    ntouched = 0;
    double *dist = ws->exact;
    int32_t local_start = count - 1;
    dijkstra(ws->lindptr, ws->lcol, ws->lprice, NULL, NULL, &local_start, 1,
             with_slack(fastest + at_start, slack), dist, ws, &ntouched);
    int32_t at = -1;
    for (int32_t i = 0; i < count; i++)
        if (ws->nodes[i] >= goal_lo && ws->nodes[i] < goal_hi && (at < 0 || dist[i] < dist[at])) at = i;

    /* _predecessors: of the tight edges into a node, the one from the node reached first, then the
     * highest-numbered */
    for (int32_t i = 0; i < count; i++) ws->pred[i] = -1;
    for (int64_t e = 0; e < edges; e++) {
        int32_t r = ws->lrow[e], c = ws->lcol[e];
        if (dist[r] + ws->lprice[e] != dist[c] || dist[c] == INFINITY) continue;
        int32_t q = ws->pred[c];
        if (q < 0 || dist[r] < dist[q] || (dist[r] == dist[q] && r > q)) ws->pred[c] = r;
    }
    int32_t length = 0;
    for (int32_t v = at; v >= 0 && length < n; v = v == local_start ? -1 : ws->pred[v]) {
        route[length] = ws->nodes[v];
        times[length++] = dist[v];
    }
    clear(dist, ws, ntouched);
    for (int32_t i = 0; i < length / 2; i++) {
        int32_t r = route[i];
        double t = times[i];
        route[i] = route[length - 1 - i];
        times[i] = times[length - 1 - i];
        route[length - 1 - i] = r;
        times[length - 1 - i] = t;
    }
    return length;
}

/* The graph's edges as fp_price reads them: per edge in row order (the straights of layer A, the turns, those of
 * layer C, then the start's), the walls it needs open. A straight needs `open_needed` walls along its line from
 * node `run_from`'s; a turn its `crossings` walls (padded with the open sentinel); a start edge its first wall
 * and `open_needed` walls from node `run_from`'s. Each node of a layer lies on at most one line of crossings:
 * line r holds line_len[r] walls (line_walls, rows of `width`) and their nodes (line_nodes, the rows joined). */
typedef struct {
    const int32_t *outer, *line_walls, *line_len, *line_nodes, *run_from, *open_needed, *turn_walls;
    const int32_t *start_first_wall, *start_run_from, *start_open_needed;
    int32_t nouter, nlines, width, nstraight, before, nturns, crossings, nstart, layer_size;
} edges_t;

/* For each wall, the edges that need it open (each edge through a wall once per crossing of it), as CSR: built
 * at the first query, so that a query that only closes walls closes only the edges through them. */
static int index_walls(workspace *ws, const edges_t *g, int32_t walls) {
    int32_t *line_of = malloc(sizeof(int32_t) * g->layer_size), *pos_of = malloc(sizeof(int32_t) * g->layer_size);
    ws->wall_indptr = calloc((size_t)walls + 2, sizeof(int32_t));
    if (!line_of || !pos_of || !ws->wall_indptr) {
        free(line_of); free(pos_of);
        return 0;
    }
    int64_t at = 0;
    for (int32_t r = 0; r < g->nlines; r++)
        for (int32_t p = 0; p < g->line_len[r]; p++, at++) line_of[g->line_nodes[at]] = r, pos_of[g->line_nodes[at]] = p;
    for (int pass = 0; pass < 2; pass++) {  /* count, then fill */
        int64_t e = 0;
#define NEEDS(wall) do { int32_t w_ = (wall); if (w_ < walls) { \
        if (pass) ws->wall_edges[ws->wall_indptr[w_ + 1]++] = (int32_t)e; else ws->wall_indptr[w_ + 2]++; } } while (0)
#define AHEAD(node, count) do { const int32_t *line_ = g->line_walls + (int64_t)line_of[node] * g->width; \
        for (int32_t k_ = 0; k_ < (count); k_++) NEEDS(line_[pos_of[node] + k_]); } while (0)
        for (int32_t i = 0; i < g->before; i++, e++) AHEAD(g->run_from[i], g->open_needed[i]);
        for (int32_t t = 0; t < g->nturns; t++, e++)
            for (int32_t k = 0; k < g->crossings; k++) NEEDS(g->turn_walls[(int64_t)k * g->nturns + t]);
        for (int32_t i = g->before; i < g->nstraight; i++, e++) AHEAD(g->run_from[i], g->open_needed[i]);
        for (int32_t i = 0; i < g->nstart; i++, e++) {
            NEEDS(g->start_first_wall[i]);
            AHEAD(g->start_run_from[i], g->start_open_needed[i]);
        }
#undef AHEAD
#undef NEEDS
        if (!pass) {
            for (int32_t w = 0; w < walls; w++) ws->wall_indptr[w + 2] += ws->wall_indptr[w + 1];
            ws->wall_edges = malloc(sizeof(int32_t) * ((size_t)ws->wall_indptr[walls + 1] + 1));
            if (!ws->wall_edges) break;
        }
    }
    free(line_of); free(pos_of);
    return ws->wall_edges != NULL;
}

/* Every edge's open flag from the walls (`open_wall`); `run` (one per node of a layer) gets the open walls
 * straight ahead of each node, counted back along each line. */
static void price_all(const edges_t *g, const uint8_t *open_wall, int16_t *run, uint8_t *open) {
    int64_t at = 0;
    for (int32_t r = 0; r < g->nlines; r++) {
        const int32_t *wall = g->line_walls + (int64_t)r * g->width;
        int16_t ahead = 0;
        for (int32_t p = g->line_len[r] - 1; p >= 0; p--) {
            ahead = open_wall[wall[p]] ? ahead + 1 : 0;
            run[g->line_nodes[at + p]] = ahead;
        }
        at += g->line_len[r];
    }
    int64_t e = 0;
    for (int32_t i = 0; i < g->before; i++, e++) open[e] = run[g->run_from[i]] >= g->open_needed[i];
    for (int32_t t = 0; t < g->nturns; t++, e++) {
        uint8_t ok = 1;
        for (int32_t k = 0; k < g->crossings; k++) ok &= open_wall[g->turn_walls[(int64_t)k * g->nturns + t]];
        open[e] = ok;
    }
    for (int32_t i = g->before; i < g->nstraight; i++, e++) open[e] = run[g->run_from[i]] >= g->open_needed[i];
    for (int32_t i = 0; i < g->nstart; i++, e++)
        open[e] = open_wall[g->start_first_wall[i]] && run[g->start_run_from[i]] >= g->start_open_needed[i];
}

/* FastestSearch.price: which edges the walls leave open (`open`, per edge in row order). A wall is open where
 * `blocked` says so and it is not an outer wall; past the real walls come the always-open and the always-closed
 * sentinels. A query that only closes walls since the last one closes the edges through them; any other works
 * every edge out again. */
void fp_price(void *p, const uint8_t *blocked, int32_t walls, const int32_t *outer, int32_t nouter,
              const int32_t *line_walls, const int32_t *line_len, int32_t nlines, int32_t width,
              const int32_t *line_nodes, int16_t *run, int32_t layer_size, int32_t nstraight, int32_t before,
              const int32_t *run_from, const int32_t *open_needed, int32_t nturns, int32_t crossings,
              const int32_t *turn_walls, int32_t nstart, const int32_t *start_first_wall,
              const int32_t *start_run_from, const int32_t *start_open_needed, uint8_t *open) {
    workspace *ws = p;
    edges_t g = {outer, line_walls, line_len, line_nodes, run_from, open_needed, turn_walls, start_first_wall,
                 start_run_from, start_open_needed, nouter, nlines, width, nstraight, before, nturns, crossings,
                 nstart, layer_size};
    int first = ws->walls == 0;
    if (first) {
        ws->open_wall = malloc((size_t)walls + 2);
        ws->was_open = malloc((size_t)walls + 2);
        if (!ws->open_wall || !ws->was_open) return;  /* not reached on any machine that runs Python */
        ws->walls = walls;
    }
    uint8_t *now = ws->was_open;  /* the new walls are worked out into the spare array, then swapped */
    for (int32_t w = 0; w < walls; w++) now[w] = blocked[w] == 0;
    for (int32_t i = 0; i < nouter; i++) now[outer[i]] = 0;
    now[walls] = 1;
    now[walls + 1] = 0;
    int opened = first;
    for (int32_t w = 0; w < walls && !opened; w++) opened = now[w] && !ws->open_wall[w];
    if (!opened && (ws->wall_edges || index_walls(ws, &g, walls))) {
        for (int32_t w = 0; w < walls; w++)
            if (!now[w] && ws->open_wall[w])
                for (int32_t j = ws->wall_indptr[w]; j < ws->wall_indptr[w + 1]; j++) open[ws->wall_edges[j]] = 0;
    } else {
        price_all(&g, now, run, open);
    }
    ws->was_open = ws->open_wall;
    ws->open_wall = now;
}

/* RouteDecoder.route: a route's nodes (`nodes`, their `times`) decoded into moves and the wall points crossed.
 * Per move: its kind (0 the start's straight of `value` cells and a half, 1 a turn of shape `value`, 2 a straight
 * of `value` steps along the walls, 3 one of `value` diagonal steps), its length in cells (straights only) and
 * its time. Points start with the start cell's centre; per point, the cell entered and the wall crossed. A
 * straight is its pieces joined, its walls counted from where it began; its cells are summed piece by piece,
 * as the Python decoder sums them. Returns the number of moves (*npoints gets the points'). */
int32_t fp_route(const int64_t *nodes, const double *times, int32_t count, int64_t start_node, int32_t layer_size,
                 int32_t side, int32_t layer_b, int32_t layer_g, int32_t cx, int32_t cy, const int32_t *step_x,
                 const int32_t *step_y, const int32_t *stride, const double *unit, const int64_t *turn_keys,
                 int64_t nturn_keys, const int32_t *turn_shapes, const int32_t *offsets, const int32_t *noffsets,
                 int32_t crossings,
                 const int64_t *wall_at, int32_t *kind, int32_t *value, double *cells, double *seconds,
                 int32_t *px, int32_t *py, int32_t *cell_x, int32_t *cell_y, int64_t *wall, int32_t *npoints) {
    int32_t moves = 0, points = 1, begin = 0;
    double length = 0.0;
    px[0] = cx, py[0] = cy;
    for (int32_t i = 0; i + 1 < count; i++) {
        int32_t wv = (int32_t)(nodes[i + 1] % layer_size), wu = (int32_t)(nodes[i] % layer_size);
        int32_t vx = (wv / 8) % side, vy = (wv / 8) / side, hv = wv % 8;
        int32_t ux = (wu / 8) % side, uy = (wu / 8) / side, h = wu % 8;
        int32_t layer = (int32_t)(nodes[i] / layer_size), next_layer = (int32_t)(nodes[i + 1] / layer_size);
        if (nodes[i] == start_node) {
            int32_t dx = step_x[hv], dy = step_y[hv], n = (abs(vx - cx) + abs(vy - cy) + 1) / 2;
            for (int32_t k = 1; k <= n; k++, points++)
                px[points] = cx + (2 * k - 1) * dx, py[points] = cy + (2 * k - 1) * dy;
            kind[moves] = 0, value[moves] = n, cells[moves] = n - 0.5, seconds[moves++] = times[i + 1] - times[i];
            begin = i + 1, length = 0.0;
            continue;
        }
        if (layer == layer_b) {
            int64_t key = nodes[i] * (start_node + 1) + nodes[i + 1], lo = 0, hi = nturn_keys;
            while (lo < hi) {  /* the first key >= key, as numpy's searchsorted */
                int64_t mid = (lo + hi) / 2;
                if (turn_keys[mid] < key) lo = mid + 1; else hi = mid;
            }
            int32_t shape = turn_shapes[lo];
            for (int32_t k = 0; k < noffsets[shape]; k++, points++)
                px[points] = ux + offsets[(shape * crossings + k) * 2],
                py[points] = uy + offsets[(shape * crossings + k) * 2 + 1];
            kind[moves] = 1, value[moves] = shape, cells[moves] = 0.0, seconds[moves++] = times[i + 1] - times[i];
            begin = i + 1, length = 0.0;
            continue;
        }
        int32_t sx = step_x[h] * stride[h], sy = step_y[h] * stride[h];
        int32_t ax = abs(sx) > 1 ? abs(sx) : 1, ay = abs(sy) > 1 ? abs(sy) : 1;
        int32_t piece_x = abs(vx - ux) / ax, piece_y = abs(vy - uy) / ay;
        length += (double)(piece_x > piece_y ? piece_x : piece_y) * unit[h];
        if (next_layer == layer_b || next_layer == layer_g) {
            int32_t wb = (int32_t)(nodes[begin] % layer_size), bx = (wb / 8) % side, by = (wb / 8) / side;
            int32_t nx = abs(vx - bx) / ax, ny = abs(vy - by) / ay, steps = nx > ny ? nx : ny;
            for (int32_t k = 1; k <= steps; k++, points++) px[points] = bx + k * sx, py[points] = by + k * sy;
            if (steps) {
                kind[moves] = h % 2 ? 3 : 2, value[moves] = steps, cells[moves] = length;
                seconds[moves++] = times[i + 1] - times[begin];
            }
        }
    }
    for (int32_t k = 1; k < points; k++) {  /* the cell beyond each wall point, and the wall */
        int32_t x = px[k], y = py[k], horizontal = x % 2 == 1;
        cell_x[k - 1] = x / 2 - (!horizontal && px[k - 1] > x);
        cell_y[k - 1] = y / 2 - (horizontal && py[k - 1] > y);
        wall[k - 1] = wall_at[(int64_t)y * side + x];
    }
    *npoints = points;
    return moves;
}
