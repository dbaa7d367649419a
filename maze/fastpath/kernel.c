/* mazelog's move graph and its fastest-path queries (maze/fastpath/query.py and maze/fastpath/bound.py say what
 * each step is for, on the scipy path that does the same where no C compiler works), compiled at first use by
 * maze/fastpath/compiled.py and called through ctypes by maze/fastpath/native.py: fp_graph builds a graph,
 * fp_query answers a query on it, fp_decode decodes its route, fp_graph_free frees it.
 *
 * Every step computes exactly what the scipy path computes, so that routes stay identical to the bit: Dijkstra's
 * times are the minimum over paths of the left-to-right sums dist[u] + w (whatever order nodes are settled in),
 * a limit keeps the nodes whose time is <= the limit (scipy's rule), and ties are broken by the rules written
 * in maze/fastpath/query.py (the lowest-numbered goal node, the earliest then highest-numbered predecessor).
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

typedef struct {
    item *at;
    int64_t count, cap;
} bucket;

#define COARSE 32                 /* the low bits of a key's double that the radix heap's buckets ignore */
#define BUCKETS (64 - COARSE + 1)

/* The working memory of one query graph of n nodes and m edges, kept between its queries: the time arrays are
 * all infinite and the flags all clear between calls (each call resets only what it touched). */
typedef struct {
    int32_t n;
    int64_t m;
    double *reduced;  /* A*'s times (reduced prices) */
    double *exact;    /* the exact search's times, local numbering */
    uint8_t *done;
    uint8_t *kept;
    int32_t *touched;
    int32_t *local;   /* node -> its number among the kept nodes */
    int32_t *nodes;   /* the kept nodes, ascending */
    int32_t *lrow, *lcol, *ledge, *lindptr, *rindptr, *rsrc, *queue, *pred;
    bucket buckets[BUCKETS]; /* the radix heap: bucket b holds keys whose coarse key's highest bit differing from
                              * `last` is b - 1 */
    uint64_t last;    /* the coarse key last taken out (keys only grow: the searches' prices are never negative) */
    int64_t low_at;   /* where in bucket 0 its lowest key is; -1 when not known */
    double last_key;  /* the key last taken out */
    int64_t queued;
    double *lprice;
    int32_t walls;          /* pricing (fp_price): 0 before the first query */
    uint8_t *open_wall;     /* per wall id and the two sentinels, the last query's: whether it is open */
    uint8_t *was_open;
    int32_t *wall_indptr;   /* the edges that need wall w open: wall_edges[wall_indptr[w]:wall_indptr[w + 1]] */
    int32_t *wall_edges;
} workspace;

/* A radix heap of nodes keyed by their tentative times: a search's keys never fall below the last one taken out
 * (its prices are never negative), and a double's bits order as the double does for keys >= 0, so a key goes in
 * the bucket of the highest bit in which its coarse key (the bits less the lowest COARSE) differs from that last
 * one's, and only the lowest non-empty bucket is ever sorted out. Bucket 0 holds the keys as coarse as the last;
 * the lowest of them is found by looking (a few keys, within 2^-17 s of each other at times of 8-16 s and closer
 * at shorter ones), where whole bits would move each entry through up to 50 buckets on its way down rather than
 * about 17. A node whose time is lowered is put in again; the searches skip an entry whose key is no
 * longer its node's time, or whose node is settled. Empty between searches (`queued` 0, `last` 0). */
static uint64_t bits(double key) {
    uint64_t b;
    memcpy(&b, &key, sizeof b);
    return b >> COARSE;
}

static int32_t bucket_of(uint64_t key, uint64_t last) { return key == last ? 0 : 64 - __builtin_clzll(key ^ last); }

static int put(bucket *b, item it) {
    if (b->count == b->cap) {
        int64_t cap = b->cap ? 2 * b->cap : 256;
        item *at = realloc(b->at, sizeof(item) * cap);
        if (!at) return 0;
        b->at = at, b->cap = cap;
    }
    b->at[b->count++] = it;
    return 1;
}

static void push(workspace *ws, int64_t *size, double key, int32_t node) {
    bucket *b = &ws->buckets[bucket_of(bits(key), ws->last)];
    if (!put(b, (item){key, node})) return;
    (*size)++;
    if (b == ws->buckets && (ws->low_at >= 0 ? key < b->at[ws->low_at].key : key == ws->last_key))
        ws->low_at = b->count - 1;  /* a key equal to the last taken out is a lowest */
}

/* The lowest key queued (the heap not empty), its entries moved into bucket 0. */
static double lowest(workspace *ws) {
    if (!ws->buckets[0].count) {
        int32_t b = 1;
        while (!ws->buckets[b].count) b++;
        bucket *from = &ws->buckets[b];
        uint64_t low = bits(from->at[0].key);
        for (int64_t i = 1; i < from->count; i++)
            if (bits(from->at[i].key) < low) low = bits(from->at[i].key);
        ws->last = low;
        for (int64_t i = 0; i < from->count; i++)  /* each to a lower bucket: it shares the bits above b with low */
            put(&ws->buckets[bucket_of(bits(from->at[i].key), low)], from->at[i]);
        from->count = 0;
        ws->low_at = -1;
    }
    bucket *b = ws->buckets;
    if (ws->low_at < 0) {  /* newest first: a key equal to the last taken out (a price of 0) ends the look */
        ws->low_at = b->count - 1;
        for (int64_t i = b->count - 2; i >= 0 && b->at[ws->low_at].key != ws->last_key; i--)
            if (b->at[i].key < b->at[ws->low_at].key) ws->low_at = i;
    }
    return b->at[ws->low_at].key;
}

static item pop(workspace *ws, int64_t *size) {
    lowest(ws);
    (*size)--;
    bucket *b = ws->buckets;
    item it = b->at[ws->low_at];
    b->at[ws->low_at] = b->at[--b->count];
    ws->low_at = -1;
    ws->last_key = it.key;
    return it;
}

static void empty(workspace *ws, int64_t *size) {
    for (int32_t b = 0; b < BUCKETS; b++) ws->buckets[b].count = 0;
    ws->last = 0, ws->low_at = -1, ws->last_key = 0.0;
    *size = 0;
}

/* Dijkstra over CSR rows (indptr, indices), the price of entry j being w[j] or infinite where `mask` says the
 * edge is closed, from what the heap holds (`size` entries, their times in dist); it stops, rather than ends, at
 * the first node whose time is over `limit`, so that A*'s try under a larger limit resumes it where the last
 * stopped (its heap and times kept) instead of settling the same nodes again. Nodes given a time are appended to
 * touched; none over `push_limit` is. Returns how many nodes it settled: every node whose time is at most the
 * limit, with the times of a search limited to it. */
static int32_t settle_to(const int32_t *indptr, const int32_t *indices, const double *w, const uint8_t *mask,
                         double limit, double push_limit, double *dist, workspace *ws, int64_t *size,
                         int32_t *ntouched) {
    int32_t settled = 0;
    while (*size && lowest(ws) <= limit) {
        item it = pop(ws, size);
        int32_t v = it.node;
        if (ws->done[v] || it.key != dist[v]) continue;  /* settled, or put in again at a lower time */
        ws->done[v] = 1;
        settled++;
        double at = dist[v];
        for (int32_t j = indptr[v]; j < indptr[v + 1]; j++) {
            int32_t u = indices[j];
            if (ws->done[u] || (mask && !mask[j])) continue;
            double next = at + w[j];
            if (next <= push_limit && next < dist[u]) {
                if (dist[u] == INFINITY) ws->touched[(*ntouched)++] = u;
                dist[u] = next;
                push(ws, size, next, u);
            }
        }
    }
    return settled;
}

/* Dijkstra from `sources` (time 0), limited to `limit`: settle_to from a heap of them, nothing over the limit put
 * in. Times go to dist (infinite on entry). Returns how many nodes it settled. */
static int32_t dijkstra(const int32_t *indptr, const int32_t *indices, const double *w, const uint8_t *mask,
                        const int32_t *sources, int32_t nsrc, double limit, double *dist, workspace *ws,
                        int32_t *ntouched) {
    int64_t size = 0;
    for (int32_t s = 0; s < nsrc; s++) {
        if (dist[sources[s]] == INFINITY) ws->touched[(*ntouched)++] = sources[s];
        dist[sources[s]] = 0.0;
        push(ws, &size, 0.0, sources[s]);
    }
    int32_t settled = settle_to(indptr, indices, w, mask, limit, limit, dist, ws, &size, ntouched);
    ws->last = 0, ws->low_at = -1, ws->last_key = 0.0;  /* empty again */
    return settled;
}

static void clear(double *dist, workspace *ws, int32_t ntouched) {
    for (int32_t i = 0; i < ntouched; i++) {
        dist[ws->touched[i]] = INFINITY;
        ws->done[ws->touched[i]] = 0;
    }
}

static void *fp_new(int32_t n, int64_t m) {
    workspace *ws = calloc(1, sizeof *ws);
    if (!ws) return NULL;
    ws->n = n;
    ws->m = m;
    ws->low_at = -1;
    ws->reduced = malloc(sizeof(double) * n);
    ws->exact = malloc(sizeof(double) * n);
    ws->done = calloc(n, 1);
    ws->kept = calloc(n + 1, 1);
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
    if (!ws->reduced || !ws->exact || !ws->done || !ws->kept || !ws->touched || !ws->local
        || !ws->nodes || !ws->lrow || !ws->lcol || !ws->ledge || !ws->lindptr || !ws->rindptr || !ws->rsrc
        || !ws->queue || !ws->pred || !ws->lprice) {
        return NULL;  /* the caller falls back; what was allocated is lost once, at start-up */
    }
    for (int32_t i = 0; i < n; i++) ws->reduced[i] = ws->exact[i] = INFINITY;
    return ws;
}

static void fp_free(void *p) {
    workspace *ws = p;
    if (!ws) return;
    free(ws->reduced); free(ws->exact); free(ws->done); free(ws->kept); free(ws->touched);
    free(ws->local); free(ws->nodes); free(ws->lrow); free(ws->lcol); free(ws->ledge); free(ws->lindptr);
    free(ws->rindptr); free(ws->rsrc); free(ws->queue); free(ws->pred); free(ws->lprice);
    free(ws->open_wall); free(ws->was_open); free(ws->wall_indptr); free(ws->wall_edges);
    for (int32_t b = 0; b < BUCKETS; b++) free(ws->buckets[b].at);
    free(ws);
}

/* TimeBound.find: the exact times to the goal (`times`, every node) by one search back from the goal nodes over
 * the reversed graph (rindptr, rindices, with each entry's price and open flag: rprice, ropen) through the open
 * edges, and the reduced prices of the forward edges (rows, indices) under them. Returns the nodes it reached. */
static int32_t fp_bound(void *p, const int32_t *rindptr, const int32_t *rindices, const double *rprice,
                 const uint8_t *ropen, const int32_t *rows, const int32_t *indices, const double *price,
                 const int32_t *goals, int32_t ngoals, double *times, double *reduced) {
    workspace *ws = p;
    int32_t ntouched = 0;
    for (int32_t i = 0; i < ws->n; i++) times[i] = INFINITY;
    int32_t cost = dijkstra(rindptr, rindices, rprice, ropen, goals, ngoals, INFINITY, times, ws, &ntouched);
    for (int32_t i = 0; i < ntouched; i++) ws->done[ws->touched[i]] = 0;
    for (int64_t e = 0; e < ws->m; e++) {
        double r = (price[e] + times[indices[e]]) - times[rows[e]];
        reduced[e] = isnan(r) ? INFINITY : (r < 0.0 ? 0.0 : r);  /* numpy: maximum(r, 0), NaN -> inf */
    }
    return cost;
}

/* Nodes (numbers below n) in ascending order, by their bytes from the lowest (a radix sort: two passes over a
 * 32x32 graph's), `spare` holding as many: linear in their count, where qsort's calls to compare cost 0.04-0.08 ms
 * over a search's 600-2100 kept nodes and a scan of n flags costs a query with known walls its few. */
static void sort_nodes(int32_t *nodes, int32_t count, int32_t n, int32_t *spare) {
    int32_t *from = nodes, *to = spare;
    for (int32_t shift = 0; shift < 32 && (n - 1) >> shift; shift += 8) {
        int32_t at[257] = {0};
        for (int32_t i = 0; i < count; i++) at[((from[i] >> shift) & 255) + 1]++;
        for (int32_t b = 0; b < 256; b++) at[b + 1] += at[b];
        for (int32_t i = 0; i < count; i++) to[at[(from[i] >> shift) & 255]++] = from[i];
        int32_t *was = from;
        from = to, to = was;
    }
    if (from != nodes) memcpy(nodes, from, sizeof(int32_t) * count);
}

static double with_slack(double seconds, double slack) { return seconds + slack * (1 + seconds); }

/* FastestSearch.search: A* from the start (the last node) on the reduced prices `astar` of the open edges under limits
 * limit0 * growth^k (k < tries, then none), each try resuming the last (settle_to), adding the nodes settled to
 * *spent; then the exact search
 * of the nodes that could lie on a fastest route (narrowed to those the goal is reached from by tight edges when
 * more than narrow_from are kept) on the prices, limited to the fastest time plus the bound at the start; and
 * the route walked back from the goal. Writes the route's nodes (start first) and their times, sets *hint to
 * A*'s reduced time to the goal, and returns the route's node count; 0 when the goal cannot be reached. */
static int32_t fp_search(void *p, const int32_t *indptr, const int32_t *indices, const double *astar, const double *price,
                  const uint8_t *open, int32_t goal_lo, int32_t goal_hi, double limit0, double growth,
                  int32_t tries, double at_start, double slack, int32_t narrow_from, int64_t *spent, double *hint,
                  int32_t *route, double *times) {
    workspace *ws = p;
    int32_t n = ws->n, start = n - 1, ntouched = 0, best = -1;
    double *reduced = ws->reduced;
    int64_t size = 0;
    reduced[start] = 0.0;
    ws->touched[ntouched++] = start;
    push(ws, &size, 0.0, start);
    for (int32_t k = 0; k <= tries && best < 0; k++) {
        double limit = k < tries ? limit0 * pow(growth, k) : INFINITY;
        *spent += settle_to(indptr, indices, astar, open, limit, INFINITY, reduced, ws, &size, &ntouched);
        for (int32_t g = goal_lo; g < goal_hi; g++)  /* the lowest-numbered of the first reached */
            if (ws->done[g] && (best < 0 || reduced[g] < reduced[best])) best = g;
    }
    empty(ws, &size);  /* the nodes over the last limit leave the heap */
    if (best < 0) {
        clear(reduced, ws, ntouched);
        return 0;
    }
    double fastest = reduced[best];
    *hint = fastest;
    double keep_to = with_slack(fastest, slack);

    /* the kept nodes, ascending, and the open edges between them, in row order */
    int32_t count = 0;
    for (int32_t i = 0; i < ntouched; i++)  /* settled: a node given a time over the limit is not */
        if (ws->done[ws->touched[i]] && reduced[ws->touched[i]] <= keep_to) ws->nodes[count++] = ws->touched[i];
    sort_nodes(ws->nodes, count, n, ws->queue);
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
    dijkstra(ws->lindptr, ws->lcol, ws->lprice, NULL, &local_start, 1,
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
static void fp_price(void *p, const uint8_t *blocked, int32_t walls, const int32_t *outer, int32_t nouter,
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
static int32_t fp_route(const int32_t *nodes, const double *times, int32_t count, int64_t start_node, int32_t layer_size,
                 int32_t side, int32_t layer_b, int32_t layer_g, int32_t cx, int32_t cy, const int32_t *step_x,
                 const int32_t *step_y, const int32_t *stride, const double *unit, const int64_t *turn_keys,
                 int64_t nturn_keys, const int32_t *turn_shapes, const int32_t *offsets, const int32_t *noffsets,
                 int32_t crossings,
                 const int32_t *wall_at, int32_t *kind, int32_t *value, double *cells, double *seconds,
                 int32_t *px, int32_t *py, int32_t *cell_x, int32_t *cell_y, int32_t *wall, int32_t *npoints) {
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
            int64_t key = (int64_t)nodes[i] * (start_node + 1) + nodes[i + 1], lo = 0, hi = nturn_keys;
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

/* ---------------------------------------------------------------------------------------------------------------
 * The move graph of one start and goal set, built here rather than in numpy (maze/fastpath/native.py passes the
 * prices, worked out in Python by the time model, and the turns' shapes), node for node and edge for edge the
 * graph maze/fastpath/build.py and FastestSearch._build_query make, in the same row order; and its queries:
 * pricing, the bound, A*, the exact search and decoding, in one call each. maze/fastpath/build.py says what the
 * layers and edges are.
 * ------------------------------------------------------------------------------------------------------------- */

enum { LAYER_A, LAYER_B, LAYER_G, LAYER_C, LAYERS };
enum { CROSSINGS = 4 };  /* the most walls a turn crosses (MAX_CROSSINGS) */
static const int32_t STEP_X[8] = {1, 1, 0, -1, -1, -1, 0, 1}, STEP_Y[8] = {0, 1, 1, 1, 0, -1, -1, -1};

/* What Python passes: per heading (0 east ... 7 south-east), whether the graph has it, its chain steps k and the
 * prices of its straights of n steps (n < 2k) braking to turn speed and free over the goal line, of k steps
 * speeding up, and of one step at top speed; per turn shape (in fastpath.build.turn_shapes' order) its headings
 * in and out, the parity of its entry point's X, its wall points and its time; the start's edges; the goal cells;
 * the wall at each point; and the query's constants (maze/fastpath/query.py). */
typedef struct {
    int32_t size, has[8], k[8], max_n;
    const double *to_turn, *to_goal;  /* [h * max_n + n] */
    double speed_up[8], cruise[8], unit[8];
    int32_t nshapes;
    const int32_t *shape_in, *shape_out, *shape_parity, *shape_noffsets, *shape_offsets;  /* offsets [s][4][2] */
    const double *shape_seconds;
    int32_t nstart;
    const int32_t *start_dst, *start_run_from, *start_open_needed, *start_first_wall;
    const double *start_seconds;
    int32_t ngoals;
    const int32_t *goal_cells;  /* y * size + x */
    const int32_t *wall_at;     /* per point; walls + 1 (closed) where there is none */
    double growth, slack, hint_margin, min_limit;
    int32_t tries, narrow_from;
} spec_t;

typedef struct {
    int32_t size, side, layer, start_node, walls, n, before, nturns;
    int64_t m;
    int32_t *wall_at, *indptr, *indices, *rows, *nodes, *local_of, *goal_nodes, ngoals, goal_lo, goal_hi;
    double *price;
    uint8_t *open;
    /* pricing (edges_t's arrays, owned) */
    int32_t *outer, nouter, *line_walls, *line_len, *line_nodes, nlines, width, nstraight;
    int32_t *run_from, *open_needed, *turn_walls, *turn_shape;
    int32_t nstart, *start_first_wall, *start_run_from, *start_open_needed;
    int16_t *run;
    /* the bound (TimeBound) */
    double *times, *reduced;
    int32_t *rindptr, *rsrc, *redge, cost;
    double *rprice;  /* the prices and open flags in the reversed rows' order: a search back reads them in turn */
    uint8_t *ropen;
    uint8_t *valid_for;
    int has_bound, has_hint;
    int64_t spent;
    double hint;
    /* decoding */
    int64_t *turn_keys;
    int32_t *turn_key_shape, *offsets, *noffsets, stride[8];
    double unit[8];
    double growth, slack, hint_margin, min_limit;
    int32_t tries, narrow_from;
    workspace *ws;
} graph_t;

typedef struct {
    int32_t *src, *dst, *run_from, *open_needed, *extra;  /* extra: end cell, goal cell or shape */
    double *cost;
    int64_t count, cap;
} edge_list;

static int grow(edge_list *l) {
    if (l->count < l->cap) return 1;
    int64_t cap = l->cap ? 2 * l->cap : 4096;
    int32_t **ints[] = {&l->src, &l->dst, &l->run_from, &l->open_needed, &l->extra};
    for (int i = 0; i < 5; i++) {
        int32_t *p = realloc(*ints[i], sizeof(int32_t) * cap);
        if (!p) return 0;
        *ints[i] = p;
    }
    double *c = realloc(l->cost, sizeof(double) * cap);
    if (!c) return 0;
    l->cost = c;
    l->cap = cap;
    return 1;
}

static int add(edge_list *l, int32_t src, int32_t dst, int32_t run_from, int32_t open_needed, double cost,
               int32_t extra) {
    if (!grow(l)) return 0;
    int64_t i = l->count++;
    l->src[i] = src, l->dst[i] = dst, l->run_from[i] = run_from, l->open_needed[i] = open_needed;
    l->cost[i] = cost, l->extra[i] = extra;
    return 1;
}

static void drop(edge_list *l) {
    free(l->src); free(l->dst); free(l->run_from); free(l->open_needed); free(l->extra); free(l->cost);
}

static int entry_point(int32_t x, int32_t y, int32_t h) {  /* StaticGraph._entry_points */
    if ((x + y) % 2 != 1) return 0;
    if (h == 0 || h == 4) return x % 2 == 0;
    if (h == 2 || h == 6) return x % 2 == 1;
    return 1;
}

static int32_t entered_cell(int32_t size, int32_t x, int32_t y, int32_t h) {  /* StaticGraph._entered_cells */
    int32_t horizontal = x % 2 == 1;
    int32_t cx = horizontal ? x / 2 : x / 2 - (STEP_X[h] < 0), cy = horizontal ? y / 2 - (STEP_Y[h] < 0) : y / 2;
    return cx >= 0 && cx < size && cy >= 0 && cy < size ? cy * size + cx : -1;
}

static int is_goal(const spec_t *s, int32_t cell) {
    for (int32_t i = 0; i < s->ngoals; i++)
        if (s->goal_cells[i] == cell) return 1;
    return 0;
}

/* A stable counting sort of `count` keys in [0, range): order[i] is the index of the i-th smallest. */
static int32_t *stable_order(const int32_t *key, int64_t count, int32_t range) {
    int32_t *at = calloc((size_t)range + 1, sizeof(int32_t)), *order = malloc(sizeof(int32_t) * (count + 1));
    if (!at || !order) {
        free(at); free(order);
        return NULL;
    }
    for (int64_t i = 0; i < count; i++) at[key[i] + 1]++;
    for (int32_t r = 0; r < range; r++) at[r + 1] += at[r];
    for (int64_t i = 0; i < count; i++) order[at[key[i]]++] = (int32_t)i;
    free(at);
    return order;
}

static void graph_free(graph_t *g) {
    if (!g) return;
    void *owned[] = {g->wall_at, g->indptr, g->indices, g->rows, g->nodes, g->local_of, g->goal_nodes, g->price,
                     g->open, g->outer, g->line_walls, g->line_len, g->line_nodes, g->run_from, g->open_needed,
                     g->turn_walls, g->turn_shape, g->start_first_wall, g->start_run_from, g->start_open_needed,
                     g->run, g->times, g->reduced, g->rindptr, g->rsrc, g->redge, g->valid_for, g->turn_keys,
                     g->turn_key_shape, g->offsets, g->noffsets, g->rprice, g->ropen};
    for (size_t i = 0; i < sizeof owned / sizeof owned[0]; i++) free(owned[i]);
    fp_free(g->ws);
    free(g);
}

void fp_graph_free(void *p) { graph_free(p); }

/* The lines of crossings (StaticGraph._build_lines): each node of a layer that crosses a wall lies on one line in
 * its heading; the lines start at the nodes no other node leads to, in heading order, then point order. */
static int build_lines(graph_t *g, const spec_t *s) {
    int32_t side = g->side, L = g->layer, closed = g->walls + 1;
    int32_t *next_node = calloc(L, sizeof(int32_t)), *next_wall = malloc(sizeof(int32_t) * L);
    uint8_t *followed = calloc(L, 1), *node_of = calloc(L, 1);
    int ok = next_node && next_wall && followed && node_of;
    if (ok) {
        for (int32_t i = 0; i < L; i++) next_wall[i] = closed;
        for (int32_t h = 0; h < 8; h++) {
            if (!s->has[h]) continue;
            int32_t sx = h % 2 ? STEP_X[h] : 2 * STEP_X[h], sy = h % 2 ? STEP_Y[h] : 2 * STEP_Y[h];
            for (int32_t p = 0; p < side * side; p++) {
                int32_t x = p % side, y = p / side, qx = x + sx, qy = y + sy;
                if (!entry_point(x, y, h)) continue;
                node_of[p * 8 + h] = 1;
                if (qx < 0 || qx >= side || qy < 0 || qy >= side) continue;
                next_node[p * 8 + h] = (qy * side + qx) * 8 + h;
                next_wall[p * 8 + h] = g->wall_at[qy * side + qx];
            }
        }
        for (int32_t v = 0; v < L; v++)
            if (node_of[v] && next_wall[v] != closed) followed[next_node[v]] = 1;
        int32_t nlines = 0, width = 0, total = 0;
        for (int32_t pass = 0; pass < 2 && ok; pass++) {
            nlines = 0, total = 0;
            for (int32_t h = 0; h < 8; h++) {
                if (!s->has[h]) continue;
                for (int32_t p = 0; p < side * side; p++) {
                    int32_t v = p * 8 + h;
                    if (!node_of[v] || followed[v]) continue;
                    int32_t len = 0;
                    for (int32_t u = v;; u = next_node[u]) {
                        if (pass) {
                            g->line_nodes[total + len] = u;
                            g->line_walls[(int64_t)nlines * width + len] = next_wall[u];
                        }
                        len++;
                        if (next_wall[u] == closed) break;
                    }
                    if (pass) g->line_len[nlines] = len;
                    if (!pass && len > width) width = len;
                    nlines++, total += len;
                }
            }
            if (!pass) {
                g->line_nodes = malloc(sizeof(int32_t) * (total + 1));
                g->line_walls = malloc(sizeof(int32_t) * ((int64_t)nlines * width + 1));
                g->line_len = malloc(sizeof(int32_t) * (nlines + 1));
                ok = g->line_nodes && g->line_walls && g->line_len;
                if (ok)
                    for (int64_t i = 0; i < (int64_t)nlines * width; i++) g->line_walls[i] = closed;
            }
        }
        g->nlines = nlines, g->width = width;
    }
    free(next_node); free(next_wall); free(followed); free(node_of);
    return ok;
}

/* The graph for one start and goal set (FastestSearch._build_query on StaticGraph's edges); NULL without memory. */
void *fp_graph(const spec_t *s) {
    graph_t *g = calloc(1, sizeof *g);
    if (!g) return NULL;
    int32_t size = s->size, side = 2 * size + 1, L = 8 * side * side;
    g->size = size, g->side = side, g->layer = L, g->start_node = LAYERS * L, g->walls = 2 * size * (size + 1);
    g->growth = s->growth, g->slack = s->slack, g->hint_margin = s->hint_margin, g->min_limit = s->min_limit;
    g->tries = s->tries, g->narrow_from = s->narrow_from;
    g->wall_at = malloc(sizeof(int32_t) * side * side);
    edge_list straight = {0}, chain = {0}, turn = {0}, ahead = {0};
    int32_t *order = NULL, *turn_order = NULL, *used_rows = NULL, *used_cols = NULL;
    int ok = g->wall_at != NULL;
    if (ok) memcpy(g->wall_at, s->wall_at, sizeof(int32_t) * side * side);
    /* straights from layer A (_build_straights): by heading, length, then point */
    for (int32_t h = 0; h < 8 && ok; h++) {
        if (!s->has[h]) continue;
        int32_t sx = h % 2 ? STEP_X[h] : 2 * STEP_X[h], sy = h % 2 ? STEP_Y[h] : 2 * STEP_Y[h];
        int32_t most = 2 * s->k[h] < 2 * size + 1 ? 2 * s->k[h] : 2 * size + 1;
        for (int32_t n = 0; n < most && ok; n++) {
            int any = 0;
            for (int32_t p = 0; p < side * side && ok; p++) {
                int32_t x = p % side, y = p / side, ex = x + n * sx, ey = y + n * sy;
                if (!entry_point(x, y, h) || ex < 0 || ex >= side || ey < 0 || ey >= side) continue;
                any = 1;
                ok = add(&straight, p * 8 + h, (ey * side + ex) * 8 + h, p * 8 + h, n, s->to_turn[h * s->max_n + n],
                         entered_cell(size, ex, ey, h));
            }
            if (!any) break;
        }
    }
    /* the chain through layer C (_build_chain): by heading; speeding up, cruising, braking, then over the line */
    for (int32_t h = 0; h < 8 && ok; h++) {
        if (!s->has[h]) continue;
        int32_t sx = h % 2 ? STEP_X[h] : 2 * STEP_X[h], sy = h % 2 ? STEP_Y[h] : 2 * STEP_Y[h], k = s->k[h];
        int32_t steps[3] = {k, 1, k}, from[3] = {LAYER_A, LAYER_C, LAYER_C}, to[3] = {LAYER_C, LAYER_C, LAYER_B};
        double cost[3] = {s->speed_up[h], s->cruise[h], s->speed_up[h]};
        for (int kind = 0; kind < 4 && ok; kind++)
            for (int32_t p = 0; p < side * side && ok; p++) {
                int32_t x = p % side, y = p / side, v = p * 8 + h;
                if (!entry_point(x, y, h)) continue;
                if (kind == 3) {
                    int32_t cell = entered_cell(size, x, y, h);
                    if (cell < 0 || is_goal(s, cell))  /* into the query's goal cells only */
                        ok = add(&chain, v + LAYER_C * L, v + LAYER_G * L, v, 0, 0.0, cell);
                    continue;
                }
                int32_t ex = x + steps[kind] * sx, ey = y + steps[kind] * sy;
                if (ex < 0 || ex >= side || ey < 0 || ey >= side) continue;
                ok = add(&chain, v + from[kind] * L, (ey * side + ex) * 8 + h + to[kind] * L, v, steps[kind],
                         cost[kind], -1);
            }
    }
    /* turns B -> A (_build_turns): by shape, then point */
    int32_t *walls_of = NULL;
    int64_t turn_cap = 0;
    for (int32_t i = 0; i < s->nshapes && ok; i++) {
        const int32_t *off = s->shape_offsets + (int64_t)i * CROSSINGS * 2;
        for (int32_t p = 0; p < side * side && ok; p++) {
            int32_t x = p % side, y = p / side, inside = (x + y) % 2 == 1 && x % 2 == s->shape_parity[i];
            for (int32_t c = 0; c < s->shape_noffsets[i] && inside; c++) {
                int32_t qx = x + off[2 * c], qy = y + off[2 * c + 1];
                inside = qx >= 0 && qx < side && qy >= 0 && qy < side;
            }
            if (!inside) continue;
            int32_t last = s->shape_noffsets[i] - 1, ex = x + off[2 * last], ey = y + off[2 * last + 1];
            ok = add(&turn, p * 8 + s->shape_in[i] + L, (ey * side + ex) * 8 + s->shape_out[i], p, 0,
                     s->shape_seconds[i], i);
            if (ok && turn.count > turn_cap) {
                turn_cap = turn.cap;
                int32_t *w = realloc(walls_of, sizeof(int32_t) * CROSSINGS * turn_cap);
                if (!w) ok = 0; else walls_of = w;
            }
            for (int32_t c = 0; c < CROSSINGS && ok; c++)
                walls_of[(turn.count - 1) * CROSSINGS + c] = c < s->shape_noffsets[i]
                    ? g->wall_at[(y + off[2 * c + 1]) * side + x + off[2 * c]] : g->walls;  /* the open sentinel */
        }
    }
    /* the query's edges that need walls ahead: all straights to B, the short ones into a goal cell to G, and the
     * chain's (those over the line into a goal cell), stably by source */
    for (int64_t i = 0; i < straight.count && ok; i++)
        ok = add(&ahead, straight.src[i], straight.dst[i] + LAYER_B * L, straight.run_from[i], straight.open_needed[i],
                 straight.cost[i], 0);
    for (int64_t i = 0; i < straight.count && ok; i++) {
        int32_t h = straight.src[i] % 8, n = straight.open_needed[i];
        if (n < s->k[h] && straight.extra[i] >= 0 && is_goal(s, straight.extra[i]))
            ok = add(&ahead, straight.src[i], straight.dst[i] + LAYER_G * L, straight.run_from[i], n,
                     s->to_goal[h * s->max_n + n], 0);
    }
    for (int64_t i = 0; i < chain.count && ok; i++)
        ok = add(&ahead, chain.src[i], chain.dst[i], chain.run_from[i], chain.open_needed[i], chain.cost[i], 0);
    if (ok) ok = (order = stable_order(ahead.src, ahead.count, LAYERS * L)) != NULL;
    if (ok) {
        for (int64_t i = 0; i < turn.count; i++) turn.src[i] -= L;  /* keys in [0, L) for the sort */
        ok = (turn_order = stable_order(turn.src, turn.count, L)) != NULL;
        for (int64_t i = 0; i < turn.count; i++) turn.src[i] += L;
    }
    int64_t m = ahead.count + turn.count + s->nstart;
    if (ok) {
        used_rows = malloc(sizeof(int32_t) * (m + 1));
        used_cols = malloc(sizeof(int32_t) * (m + 1));
        g->price = malloc(sizeof(double) * (m + 1));
        g->run_from = malloc(sizeof(int32_t) * (ahead.count + 1));
        g->open_needed = malloc(sizeof(int32_t) * (ahead.count + 1));
        g->turn_walls = malloc(sizeof(int32_t) * (CROSSINGS * turn.count + 1));
        g->turn_shape = malloc(sizeof(int32_t) * (turn.count + 1));
        ok = used_rows && used_cols && g->price && g->run_from && g->open_needed && g->turn_walls && g->turn_shape;
    }
    if (ok) {
        int64_t before = 0, e = 0;
        while (before < ahead.count && ahead.src[order[before]] < LAYER_B * L) before++;
        for (int64_t i = 0; i < ahead.count; i++) {
            int32_t j = order[i];
            g->run_from[i] = ahead.run_from[j], g->open_needed[i] = ahead.open_needed[j];
        }
        for (int64_t i = 0; i < before; i++, e++)
            used_rows[e] = ahead.src[order[i]], used_cols[e] = ahead.dst[order[i]], g->price[e] = ahead.cost[order[i]];
        for (int64_t t = 0; t < turn.count; t++, e++) {
            int32_t j = turn_order[t];
            used_rows[e] = turn.src[j], used_cols[e] = turn.dst[j], g->price[e] = turn.cost[j];
            g->turn_shape[t] = turn.extra[j];
            for (int32_t c = 0; c < CROSSINGS; c++) g->turn_walls[(int64_t)c * turn.count + t] = walls_of[j * CROSSINGS + c];
        }
        for (int64_t i = before; i < ahead.count; i++, e++)
            used_rows[e] = ahead.src[order[i]], used_cols[e] = ahead.dst[order[i]], g->price[e] = ahead.cost[order[i]];
        for (int32_t i = 0; i < s->nstart; i++, e++)
            used_rows[e] = g->start_node, used_cols[e] = s->start_dst[i], g->price[e] = s->start_seconds[i];
        g->before = (int32_t)before, g->nturns = (int32_t)turn.count, g->nstraight = (int32_t)ahead.count;
        g->m = m;
        /* the nodes with an edge, numbered in order (the start, the highest, last) */
        g->local_of = malloc(sizeof(int32_t) * (g->start_node + 1));
        ok = g->local_of != NULL;
    }
    if (ok) {
        for (int32_t v = 0; v <= g->start_node; v++) g->local_of[v] = -1;
        for (int64_t e = 0; e < m; e++) g->local_of[used_rows[e]] = g->local_of[used_cols[e]] = 0;
        int32_t n = 0;
        for (int32_t v = 0; v <= g->start_node; v++)
            if (!g->local_of[v]) g->local_of[v] = n++;
        g->n = n;
        g->nodes = malloc(sizeof(int32_t) * n);
        g->indptr = calloc((size_t)n + 1, sizeof(int32_t));
        g->rows = malloc(sizeof(int32_t) * (m + 1));
        g->indices = malloc(sizeof(int32_t) * (m + 1));
        ok = g->nodes && g->indptr && g->rows && g->indices;
    }
    if (ok) {
        for (int32_t v = 0; v <= g->start_node; v++)
            if (g->local_of[v] >= 0) g->nodes[g->local_of[v]] = v;
        for (int64_t e = 0; e < m; e++) {
            g->rows[e] = g->local_of[used_rows[e]], g->indices[e] = g->local_of[used_cols[e]];
            g->indptr[g->rows[e] + 1]++;
        }
        for (int32_t i = 0; i < g->n; i++) g->indptr[i + 1] += g->indptr[i];
        g->goal_lo = g->n, g->goal_hi = g->n;
        for (int32_t i = g->n - 1; i >= 0; i--) {
            if (g->nodes[i] >= LAYER_G * L) g->goal_lo = i;
            if (g->nodes[i] >= (LAYER_G + 1) * L) g->goal_hi = i;
        }
        uint8_t *is_goal_node = calloc(g->n, 1);
        g->goal_nodes = malloc(sizeof(int32_t) * (g->n + 1));
        ok = is_goal_node && g->goal_nodes;
        if (ok) {
            for (int64_t e = 0; e < m; e++)
                if (g->indices[e] >= g->goal_lo && g->indices[e] < g->goal_hi) is_goal_node[g->indices[e]] = 1;
            for (int32_t i = g->goal_lo; i < g->goal_hi; i++)
                if (is_goal_node[i]) g->goal_nodes[g->ngoals++] = i;
        }
        free(is_goal_node);
    }
    /* pricing: the start's edges, the outer walls, the lines, the open flags and the per-node runs */
    if (ok) {
        g->nstart = s->nstart;
        int32_t *copies[3] = {NULL, NULL, NULL};
        const int32_t *from[3] = {s->start_first_wall, s->start_run_from, s->start_open_needed};
        for (int i = 0; i < 3 && ok; i++) {
            copies[i] = malloc(sizeof(int32_t) * (s->nstart + 1));
            ok = copies[i] != NULL;
            if (ok) memcpy(copies[i], from[i], sizeof(int32_t) * s->nstart);
        }
        g->start_first_wall = copies[0], g->start_run_from = copies[1], g->start_open_needed = copies[2];
        g->outer = malloc(sizeof(int32_t) * 8 * side);
        g->open = calloc((size_t)m + 1, 1);
        g->run = calloc(L, sizeof(int16_t));
        ok = ok && g->outer && g->open && g->run;
    }
    if (ok) {
        for (int32_t p = 0; p < side * side; p++) {
            int32_t x = p % side, y = p / side;
            if ((x + y) % 2 == 1 && (x == 0 || y == 0 || x == side - 1 || y == side - 1))
                g->outer[g->nouter++] = g->wall_at[p];
        }
        ok = build_lines(g, s);
    }
    /* the bound's arrays: the edges by destination */
    if (ok) {
        int32_t *by_dst = stable_order(g->indices, m, g->n);
        g->redge = by_dst;
        g->rindptr = calloc((size_t)g->n + 1, sizeof(int32_t));
        g->rsrc = malloc(sizeof(int32_t) * (m + 1));
        g->times = malloc(sizeof(double) * g->n);
        g->reduced = malloc(sizeof(double) * (m + 1));
        g->valid_for = malloc((size_t)g->walls + 1);
        g->rprice = malloc(sizeof(double) * (m + 1));
        g->ropen = malloc((size_t)m + 1);
        ok = by_dst && g->rindptr && g->rsrc && g->times && g->reduced && g->valid_for && g->rprice && g->ropen;
        if (ok) {
            for (int64_t e = 0; e < m; e++) g->rindptr[g->indices[e] + 1]++;
            for (int32_t i = 0; i < g->n; i++) g->rindptr[i + 1] += g->rindptr[i];
            for (int64_t i = 0; i < m; i++) g->rsrc[i] = g->rows[by_dst[i]], g->rprice[i] = g->price[by_dst[i]];
        }
    }
    /* decoding: the turns' keys (source * node count + destination, global numbers), sorted, with their shapes */
    if (ok) {
        g->turn_keys = malloc(sizeof(int64_t) * (turn.count + 1));
        g->turn_key_shape = malloc(sizeof(int32_t) * (turn.count + 1));
        g->offsets = malloc(sizeof(int32_t) * (s->nshapes * CROSSINGS * 2 + 1));
        g->noffsets = malloc(sizeof(int32_t) * (s->nshapes + 1));
        ok = g->turn_keys && g->turn_key_shape && g->offsets && g->noffsets;
    }
    if (ok) {
        memcpy(g->offsets, s->shape_offsets, sizeof(int32_t) * s->nshapes * CROSSINGS * 2);
        memcpy(g->noffsets, s->shape_noffsets, sizeof(int32_t) * s->nshapes);
        for (int32_t h = 0; h < 8; h++) g->stride[h] = h % 2 ? 1 : 2, g->unit[h] = s->unit[h];
        int64_t count = g->start_node + 1;
        for (int64_t t = 0; t < turn.count; t++) {  /* by source already: sort each source's few by destination */
            int32_t j = turn_order[t];
            int64_t key = (int64_t)turn.src[j] * count + turn.dst[j], i = t;
            while (i > 0 && g->turn_keys[i - 1] > key) {
                g->turn_keys[i] = g->turn_keys[i - 1], g->turn_key_shape[i] = g->turn_key_shape[i - 1];
                i--;
            }
            g->turn_keys[i] = key, g->turn_key_shape[i] = turn.extra[j];
        }
        g->ws = fp_new(g->n, m);
        ok = g->ws != NULL;
    }
    drop(&straight); drop(&chain); drop(&turn); drop(&ahead);
    free(order); free(turn_order); free(used_rows); free(used_cols); free(walls_of);
    if (!ok) {
        graph_free(g);
        return NULL;
    }
    return g;
}

int32_t fp_graph_nodes(void *p) { return ((graph_t *)p)->n; }

/* One query (MoveGraph.fastest up to decoding): which edges the walls `blocked` leave open; the bound found again
 * where it is stale (none yet, a wall it had closed is open, or A* has spent as much under it as finding it again
 * costs); A* from a limit over the last answer, then the exact search. Writes the route's nodes (global numbers,
 * the start first) and times; returns their count, 0 when the goal cannot be reached. */
int32_t fp_query(void *p, const uint8_t *blocked, int32_t *route, double *times) {
    graph_t *g = p;
    fp_price(g->ws, blocked, g->walls, g->outer, g->nouter, g->line_walls, g->line_len, g->nlines, g->width,
             g->line_nodes, g->run, g->layer, g->nstraight, g->before, g->run_from, g->open_needed, g->nturns,
             CROSSINGS, g->turn_walls, g->nstart, g->start_first_wall, g->start_run_from, g->start_open_needed,
             g->open);
    int stale = !g->has_bound || g->spent > g->cost;
    for (int32_t w = 0; w < g->walls && !stale; w++) stale = g->valid_for[w] > blocked[w];
    if (stale) {
        for (int64_t j = 0; j < g->m; j++) g->ropen[j] = g->open[g->redge[j]];
        g->cost = fp_bound(g->ws, g->rindptr, g->rsrc, g->rprice, g->ropen, g->rows, g->indices, g->price,
                           g->goal_nodes, g->ngoals, g->times, g->reduced);
        memcpy(g->valid_for, blocked, (size_t)g->walls);
        g->has_bound = 1, g->spent = 0, g->has_hint = 0;  /* the last answer was under another bound */
    }
    double limit0 = (g->has_hint ? g->hint : 0.0) * g->hint_margin;
    if (limit0 < g->min_limit) limit0 = g->min_limit;
    int64_t spent = 0;
    double hint = 0.0;
    int32_t length = fp_search(g->ws, g->indptr, g->indices, g->reduced, g->price, g->open, g->goal_lo, g->goal_hi,
                               limit0, g->growth, g->tries, g->times[g->n - 1], g->slack, g->narrow_from, &spent,
                               &hint, route, times);
    g->spent += spent;
    if (!length) return 0;
    g->hint = hint, g->has_hint = 1;
    for (int32_t i = 0; i < length; i++) route[i] = g->nodes[route[i]];
    return length;
}

/* A route fp_query found, decoded (fp_route) from the start cell's centre (cx, cy). */
int32_t fp_decode(void *p, const int32_t *nodes, const double *times, int32_t count, int32_t cx, int32_t cy,
                  int32_t *kind, int32_t *value, double *cells, double *seconds, int32_t *px, int32_t *py,
                  int32_t *cell_x, int32_t *cell_y, int32_t *wall, int32_t *npoints) {
    graph_t *g = p;
    return fp_route(nodes, times, count, g->start_node, g->layer, g->side, LAYER_B, LAYER_G, cx, cy, STEP_X, STEP_Y,
                    g->stride, g->unit, g->turn_keys, g->nturns, g->turn_key_shape, g->offsets, g->noffsets,
                    CROSSINGS, g->wall_at, kind, value, cells, seconds, px, py, cell_x, cell_y, wall, npoints);
}
