/* mazelog's move graph and its fastest-path queries (maze/fastpath/query.py and maze/fastpath/bound.py say what
 * each step is for, on the scipy path that does the same where no C compiler works), compiled at first use by
 * maze/fastpath/compiled.py and called through ctypes by maze/fastpath/native.py: fp_graph builds a graph,
 * fp_query answers a query on it, fp_decode decodes its route, fp_graph_free frees it.
 *
 * Every step the route depends on computes exactly what the scipy path computes, so that routes stay identical to
 * the bit: Dijkstra's times are the minimum over paths of the left-to-right sums dist[u] + w (whatever order nodes
 * are settled in), a limit keeps the nodes whose time is <= the limit (scipy's rule), and ties are broken by the
 * rules written in maze/fastpath/query.py (the lowest-numbered goal node, the earliest then highest-numbered
 * predecessor). A* differs: it is resumed from query to query (fp_search), which changes which nodes it keeps
 * besides those of the fastest routes, and so neither the exact search's times nor the route.
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

/* A 4-ary heap of nodes keyed by their times, each node in it at most once (`where`): a node whose time falls moves
 * up rather than being put in again, and A*'s queue, kept from query to query, takes the times of the nodes a
 * query repairs (`invalidate`), which may lie below the last taken out. */
typedef struct {
    item *at;
    int32_t *where;  /* per node, its place in `at`; -1 where it is not in the heap */
    int32_t count;
} heap;

/* The working memory of one query graph of n nodes and m edges, kept between its queries: the time arrays are
 * all infinite and the flags all clear between calls (each call resets only what it touched), but for A*'s, which
 * are kept from one query to the next (fp_search). */
typedef struct {
    int32_t n;
    int64_t m;
    double *reduced;  /* A*'s times (sums of reduced prices) */
    uint8_t *settled; /* A*'s settled nodes */
    int32_t *parent;  /* per node, the edge that gave it its A* time; -1 the start, -2 never reached */
    int32_t *reached; /* the nodes A* has given a time since `astar_reset` */
    int32_t nreached;
    heap queue;       /* A*'s unsettled nodes with a time */
    heap scratch;     /* the other searches' (empty between calls) */
    double *exact;    /* the exact search's times, local numbering */
    uint8_t *done;
    uint8_t *kept;
    int32_t *touched;
    int32_t *local;   /* node -> its number among the kept nodes */
    int32_t *nodes;   /* the kept nodes, ascending */
    int32_t *lrow, *lcol, *ledge, *lindptr, *list, *pred;
    double *lprice;
    int32_t walls;          /* pricing (fp_price): 0 before the first query */
    uint8_t *open_wall;     /* per wall id and the two sentinels, the last query's: whether it is open */
    uint8_t *was_open;
    int32_t *wall_indptr;   /* the edges that need wall w open: wall_edges[wall_indptr[w]:wall_indptr[w + 1]] */
    int32_t *wall_edges;
    int32_t *closed;        /* the edges the last fp_price closed, when it only closed walls */
    int64_t nclosed;
} workspace;

static void sift_up(heap *h, int32_t i) {
    item it = h->at[i];
    for (int32_t up = (i - 1) / 4; i > 0 && h->at[up].key > it.key; i = up, up = (i - 1) / 4) {
        h->at[i] = h->at[up];
        h->where[h->at[i].node] = i;
    }
    h->at[i] = it;
    h->where[it.node] = i;
}

static void sift_down(heap *h, int32_t i) {
    item it = h->at[i];
    for (;;) {
        int32_t low = -1;
        double key = it.key;
        for (int32_t c = 4 * i + 1; c <= 4 * i + 4 && c < h->count; c++)
            if (h->at[c].key < key) key = h->at[c].key, low = c;
        if (low < 0) break;
        h->at[i] = h->at[low];
        h->where[h->at[i].node] = i;
        i = low;
    }
    h->at[i] = it;
    h->where[it.node] = i;
}

/* Queues `node` at `key`, or moves it there. */
static void heap_set(heap *h, double key, int32_t node) {
    int32_t i = h->where[node];
    if (i < 0) {
        h->at[i = h->count++] = (item){key, node};
        sift_up(h, i);
        return;
    }
    double was = h->at[i].key;
    h->at[i].key = key;
    if (key < was) sift_up(h, i); else sift_down(h, i);
}

static void heap_remove(heap *h, int32_t node) {
    int32_t i = h->where[node];
    if (i < 0) return;
    h->where[node] = -1;
    item last = h->at[--h->count];
    if (i == h->count) return;
    h->at[i] = last;
    sift_up(h, i);
    sift_down(h, h->where[last.node]);
}

/* Takes out the lowest (the heap not empty): its hole sinks to a leaf by the lower children, and the last item rises
 * from there (it mostly stays low: fewer compares than sinking it from the top). */
static item heap_pop(heap *h) {
    item top = h->at[0], last = h->at[--h->count];
    h->where[top.node] = -1;
    int32_t i = 0, count = h->count;
    if (!count) return top;
    for (int32_t c = 1; c < count; c = 4 * i + 1) {
        int32_t low = c, end = c + 4 < count ? c + 4 : count;
        for (int32_t k = c + 1; k < end; k++)
            if (h->at[k].key < h->at[low].key) low = k;
        h->at[i] = h->at[low];
        h->where[h->at[i].node] = i;
        i = low;
    }
    h->at[i] = last;
    sift_up(h, i);
    return top;
}

/* Dijkstra over CSR rows (indptr, indices) priced w from `source` (time 0), limited to `limit`: no node whose time
 * is over it is given one (scipy's rule). Times go to dist (infinite on entry); the nodes given one are appended to
 * touched. */
static void dijkstra(const int32_t *indptr, const int32_t *indices, const double *w, int32_t source, double limit,
                     double *dist, workspace *ws, int32_t *ntouched) {
    heap *h = &ws->scratch;
    ws->touched[(*ntouched)++] = source;
    dist[source] = 0.0;
    heap_set(h, 0.0, source);
    while (h->count) {
        item it = heap_pop(h);
        ws->done[it.node] = 1;
        for (int32_t j = indptr[it.node]; j < indptr[it.node + 1]; j++) {
            int32_t u = indices[j];
            if (ws->done[u]) continue;
            double next = it.key + w[j];
            if (next <= limit && next < dist[u]) {
                if (dist[u] == INFINITY) ws->touched[(*ntouched)++] = u;
                dist[u] = next;
                heap_set(h, next, u);
            }
        }
    }
}

static void clear(double *dist, workspace *ws, int32_t ntouched) {
    for (int32_t i = 0; i < ntouched; i++) {
        dist[ws->touched[i]] = INFINITY;
        ws->done[ws->touched[i]] = 0;
    }
}

static int new_heap(heap *h, int32_t n) {
    h->at = malloc(sizeof(item) * n);
    h->where = malloc(sizeof(int32_t) * n);
    if (!h->at || !h->where) return 0;
    for (int32_t i = 0; i < n; i++) h->where[i] = -1;
    return 1;
}

static void *fp_new(int32_t n, int64_t m) {
    workspace *ws = calloc(1, sizeof *ws);
    if (!ws) return NULL;
    ws->n = n;
    ws->m = m;
    ws->reduced = malloc(sizeof(double) * n);
    ws->settled = calloc(n, 1);
    ws->parent = malloc(sizeof(int32_t) * n);
    ws->reached = malloc(sizeof(int32_t) * n);
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
    ws->list = malloc(sizeof(int32_t) * (n + 1));
    ws->pred = malloc(sizeof(int32_t) * n);
    ws->lprice = malloc(sizeof(double) * (m + 1));
    if (!ws->reduced || !ws->settled || !ws->parent || !ws->reached || !new_heap(&ws->queue, n)
        || !new_heap(&ws->scratch, n) || !ws->exact || !ws->done || !ws->kept || !ws->touched || !ws->local
        || !ws->nodes || !ws->lrow || !ws->lcol || !ws->ledge || !ws->lindptr || !ws->list || !ws->pred
        || !ws->lprice) {
        return NULL;  /* the caller falls back; what was allocated is lost once, at start-up */
    }
    for (int32_t i = 0; i < n; i++) ws->reduced[i] = ws->exact[i] = INFINITY, ws->parent[i] = -2;
    return ws;
}

static void fp_free(void *p) {
    workspace *ws = p;
    if (!ws) return;
    free(ws->reduced); free(ws->settled); free(ws->parent); free(ws->reached); free(ws->queue.at);
    free(ws->queue.where); free(ws->scratch.at); free(ws->scratch.where); free(ws->exact); free(ws->done);
    free(ws->kept); free(ws->touched); free(ws->local); free(ws->nodes); free(ws->lrow); free(ws->lcol);
    free(ws->ledge); free(ws->lindptr); free(ws->list); free(ws->pred); free(ws->lprice);
    free(ws->open_wall); free(ws->was_open); free(ws->wall_indptr); free(ws->wall_edges); free(ws->closed);
    free(ws);
}

/* TimeBound.find: the exact times to the goal (`times`) of the nodes the start reaches through the open edges, by
 * one search back from the goal nodes over the reversed graph (rindptr, rindices, each entry priced rprice, and
 * redge the forward edge it is, whose open flag says whether it may be taken); infinite elsewhere. A* never reaches
 * a node the start does not, and walls only close while a bound is kept, so those nodes need none: a third of a
 * 32x32 diagonal graph's that reach the goal (27 500 to 19 200 on japan2017hef's first query). Returns the edges
 * it scanned, forwards and back: what finding the bound costs, in the unit fp_query weighs A*'s work in. */
static int32_t fp_bound(void *p, const int32_t *rindptr, const int32_t *rindices, const double *rprice,
                        const int32_t *redge, const int32_t *indptr, const int32_t *indices, const uint8_t *open,
                        const int32_t *goals, int32_t ngoals, double *times) {
    workspace *ws = p;
    uint8_t *reach = ws->kept;  /* clear again by the end */
    int32_t *list = ws->list, tail = 0, scanned = 0, ntouched = 0;
    reach[ws->n - 1] = 1, list[tail++] = ws->n - 1;  /* the start */
    for (int32_t at = 0; at < tail; at++)
        for (int32_t j = indptr[list[at]]; j < indptr[list[at] + 1]; j++, scanned++)
            if (open[j] && !reach[indices[j]]) reach[indices[j]] = 1, list[tail++] = indices[j];
    for (int32_t i = 0; i < ws->n; i++) times[i] = INFINITY;
    heap *h = &ws->scratch;
    for (int32_t g = 0; g < ngoals; g++) {
        ws->touched[ntouched++] = goals[g];
        times[goals[g]] = 0.0;
        heap_set(h, 0.0, goals[g]);
    }
    while (h->count) {
        item it = heap_pop(h);
        ws->done[it.node] = 1;
        scanned += rindptr[it.node + 1] - rindptr[it.node];
        for (int32_t j = rindptr[it.node]; j < rindptr[it.node + 1]; j++) {
            int32_t u = rindices[j];
            if (ws->done[u] || !reach[u] || !open[redge[j]]) continue;
            double next = it.key + rprice[j];
            if (next < times[u]) {
                if (times[u] == INFINITY) ws->touched[ntouched++] = u;
                times[u] = next;
                heap_set(h, next, u);
            }
        }
    }
    for (int32_t i = 0; i < ntouched; i++) ws->done[ws->touched[i]] = 0;
    for (int32_t at = 0; at < tail; at++) reach[list[at]] = 0;
    return scanned;
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

/* The reduced price of edge e from node `from` to node `to` under the bound h: its price plus the fall in the bound,
 * as TimeBound works them out (numpy: maximum(r, 0), NaN -> inf), at the few edges A* reads rather than at every
 * edge each time the bound is found. */
static double reduced_price(const double *price, const double *h, int32_t e, int32_t from, int32_t to) {
    double r = (price[e] + h[to]) - h[from];
    return isnan(r) ? INFINITY : (r < 0.0 ? 0.0 : r);
}

/* Forgets A*'s times: its bound changed, or a wall opened (a time may fall, which `invalidate` cannot repair). */
static void astar_reset(workspace *ws) {
    for (int32_t i = 0; i < ws->nreached; i++) {
        int32_t v = ws->reached[i];
        ws->reduced[v] = INFINITY, ws->settled[v] = 0, ws->parent[v] = -2, ws->queue.where[v] = -1;
    }
    ws->nreached = 0, ws->queue.count = 0;
}

/* Whether another settled node gives v the same time through an open edge (its parent then): v keeps its time. A
 * parent lost later loses v too, through the edge recorded. */
static int reparent(workspace *ws, int32_t v, const double *price, const double *h, const uint8_t *open,
                    const int32_t *rindptr, const int32_t *rsrc, const int32_t *redge) {
    for (int32_t k = rindptr[v]; k < rindptr[v + 1]; k++) {
        int32_t e = redge[k], u = rsrc[k];
        if (open[e] && ws->settled[u] && ws->reduced[u] + reduced_price(price, h, e, u, v) == ws->reduced[v]) {
            ws->parent[v] = e;
            return 1;
        }
    }
    return 0;
}

/* A*'s times after the edges `closed` close (and none opens), under the same bound: closing only raises times,
 * and only those of the nodes whose time came through a closed edge (parent[v], the edge that gave v its time),
 * directly or through such a node, unless another node gives them the same time (`reparent`). They are forgotten
 * and given again the best time through the settled nodes whose times stand (the minimum over paths, bit for bit
 * what a search from scratch finds), and queued; A* then resumes (`fp_search`). A query comes because a wall on
 * the last route closed, so this touches the nodes past it that A* had reached through it, where a search from
 * scratch settles again every node the last one did (1 300-3 500 a query on japan2017hef once walls have closed
 * on a route since the bound was found). Returns the edges it scanned for the nodes forgotten. */
static int32_t invalidate(workspace *ws, const int32_t *indptr, const int32_t *indices, const double *price,
                          const double *h, const uint8_t *open, const int32_t *rindptr, const int32_t *rsrc,
                          const int32_t *redge, const int32_t *closed, int64_t nclosed) {
    int32_t *lost = ws->list, count = 0;
    double *r = ws->reduced;
    for (int64_t i = 0; i < nclosed; i++) {
        int32_t v = indices[closed[i]];
        if (r[v] < INFINITY && ws->parent[v] == closed[i] && !reparent(ws, v, price, h, open, rindptr, rsrc, redge))
            r[v] = INFINITY, ws->settled[v] = 0, lost[count++] = v, heap_remove(&ws->queue, v);
    }
    for (int32_t at = 0; at < count; at++)
        for (int32_t j = indptr[lost[at]]; j < indptr[lost[at] + 1]; j++) {
            int32_t v = indices[j];
            if (r[v] < INFINITY && ws->parent[v] == j && !reparent(ws, v, price, h, open, rindptr, rsrc, redge))
                r[v] = INFINITY, ws->settled[v] = 0, lost[count++] = v, heap_remove(&ws->queue, v);
        }
    int32_t scanned = 0;
    for (int32_t at = 0; at < count; at++) {
        int32_t v = lost[at];
        scanned += (rindptr[v + 1] - rindptr[v]) + (indptr[v + 1] - indptr[v]);
        for (int32_t k = rindptr[v]; k < rindptr[v + 1]; k++) {
            int32_t e = redge[k], u = rsrc[k];
            if (!open[e] || !ws->settled[u]) continue;
            double next = r[u] + reduced_price(price, h, e, u, v);
            if (next < r[v]) r[v] = next, ws->parent[v] = e;
        }
        if (r[v] < INFINITY) heap_set(&ws->queue, r[v], v);
    }
    return scanned;
}

/* FastestSearch.search: A* from the start (the last node) on the reduced prices of the open edges under the bound
 * h (`reduced_price`), resumed from the last query's (`invalidate`), until every node no slower than the fastest
 * goal node (with slack for rounding) is settled, adding the edges it scanned to *spent; then the exact search of
 * the nodes that could lie on a fastest route (those the goal is reached from by tight edges, found back from the
 * goal over the reversed edges rindptr, rsrc, redge) on the prices, limited to the fastest time plus the bound at
 * the start; and the route walked back from the goal. Writes the route's nodes (start first) and their times and
 * returns the route's node count; 0 when the goal cannot be reached. A* needs no limits (the scipy path's): it
 * stops where the fastest goal node is known, and which nodes it keeps besides those of the fastest routes does
 * not change the route (`FastestSearch.search`); nor does it need to keep them all to find those, every query. */
static int32_t fp_search(void *p, const int32_t *indptr, const int32_t *indices, const double *h,
                         const double *price, const uint8_t *open, const int32_t *rindptr, const int32_t *rsrc,
                         const int32_t *redge, int32_t goal_lo, int32_t goal_hi, double at_start, double slack,
                         int64_t *spent, int32_t *route, double *times) {
    workspace *ws = p;
    int32_t n = ws->n, start = n - 1, ntouched = 0, best = -1;
    double *reduced = ws->reduced;
    if (!ws->nreached) {
        reduced[start] = 0.0, ws->parent[start] = -1, ws->reached[ws->nreached++] = start;
        heap_set(&ws->queue, 0.0, start);
    }
    for (int32_t g = goal_lo; g < goal_hi; g++)  /* the lowest-numbered of the fastest settled */
        if (ws->settled[g] && (best < 0 || reduced[g] < reduced[best])) best = g;
    while (ws->queue.count) {
        item top = ws->queue.at[0];
        int32_t v = top.node;
        if (best >= 0 && top.key > with_slack(reduced[best], slack)) break;
        heap_pop(&ws->queue);
        ws->settled[v] = 1;
        *spent += indptr[v + 1] - indptr[v];
        int faster = best < 0 || top.key < reduced[best] || (top.key == reduced[best] && v < best);
        if (v >= goal_lo && v < goal_hi && faster) best = v;
        for (int32_t j = indptr[v]; j < indptr[v + 1]; j++) {
            int32_t u = indices[j];
            if (!open[j] || ws->settled[u]) continue;
            double next = top.key + reduced_price(price, h, j, v, u);
            if (next < reduced[u]) {
                if (ws->parent[u] == -2) ws->reached[ws->nreached++] = u;
                reduced[u] = next, ws->parent[u] = j;
                heap_set(&ws->queue, next, u);
            }
        }
    }
    if (best < 0) return 0;
    double fastest = reduced[best], keep_to = with_slack(fastest, slack), margin = keep_to - fastest;

    /* _on_fastest_routes: back from the kept goal nodes over tight edges between kept nodes */
    uint8_t *on = ws->kept;  /* clear again by the end */
    int32_t count = 0;
    for (int32_t g = goal_lo; g < goal_hi; g++)
        if (ws->settled[g] && reduced[g] <= keep_to) on[g] = 1, ws->nodes[count++] = g;
    for (int32_t at = 0; at < count; at++) {
        int32_t v = ws->nodes[at];
        for (int32_t k = rindptr[v]; k < rindptr[v + 1]; k++) {
            int32_t u = rsrc[k], e = redge[k];
            if (on[u] || !open[e] || !ws->settled[u] || reduced[u] > keep_to) continue;
            if (reduced[u] + reduced_price(price, h, e, u, v) > reduced[v] + margin) continue;
            on[u] = 1, ws->nodes[count++] = u;
        }
    }
    sort_nodes(ws->nodes, count, n, ws->list);
    for (int32_t i = 0; i < count; i++) ws->local[ws->nodes[i]] = i;
    int64_t edges = 0;
    for (int32_t i = 0; i < count; i++) {
        int32_t v = ws->nodes[i];
        for (int32_t j = indptr[v]; j < indptr[v + 1]; j++) {
            if (!open[j] || !on[indices[j]]) continue;
            ws->lrow[edges] = i;
            ws->lcol[edges] = ws->local[indices[j]];
            ws->ledge[edges++] = j;
        }
    }
    for (int32_t i = 0; i < count; i++) on[ws->nodes[i]] = 0;

    /* the exact search of the sub graph, from the start (its last node) */
    memset(ws->lindptr, 0, sizeof(int32_t) * (count + 1));
    for (int64_t e = 0; e < edges; e++) {
        ws->lindptr[ws->lrow[e] + 1]++;
        ws->lprice[e] = price[ws->ledge[e]];
    }
    for (int32_t i = 0; i < count; i++) ws->lindptr[i + 1] += ws->lindptr[i];
    double *dist = ws->exact;
    int32_t local_start = count - 1;
    dijkstra(ws->lindptr, ws->lcol, ws->lprice, local_start, with_slack(fastest + at_start, slack), dist, ws,
             &ntouched);
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
 * with the graph (fp_graph; 3 ms on a 32x32 diagonal graph), so that a query that only closes walls closes only
 * the edges through them, and lists them (ws->closed) for A*. */
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
            ws->closed = malloc(sizeof(int32_t) * ((size_t)ws->wall_indptr[walls + 1] + 1));
            if (!ws->wall_edges || !ws->closed) break;
        }
    }
    free(line_of); free(pos_of);
    return ws->wall_edges && ws->closed;
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
 * sentinels. A query that only closes walls since the last one closes the edges through them, lists them in
 * ws->closed for A* (`invalidate`) and returns 1; any other works every edge out again and returns 0. */
static int fp_price(void *p, const uint8_t *blocked, int32_t walls, const int32_t *outer, int32_t nouter,
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
        if (!ws->open_wall || !ws->was_open) return 0;  /* not reached on any machine that runs Python */
        ws->walls = walls;
    }
    uint8_t *now = ws->was_open;  /* the new walls are worked out into the spare array, then swapped */
    for (int32_t w = 0; w < walls; w++) now[w] = blocked[w] == 0;
    for (int32_t i = 0; i < nouter; i++) now[outer[i]] = 0;
    now[walls] = 1;
    now[walls + 1] = 0;
    int opened = first;
    for (int32_t w = 0; w < walls && !opened; w++) opened = now[w] && !ws->open_wall[w];
    int closing = !opened;
    ws->nclosed = 0;
    if (closing) {
        for (int32_t w = 0; w < walls; w++)
            if (!now[w] && ws->open_wall[w])
                for (int32_t j = ws->wall_indptr[w]; j < ws->wall_indptr[w + 1]; j++) {
                    int32_t e = ws->wall_edges[j];
                    if (open[e]) open[e] = 0, ws->closed[ws->nclosed++] = e;
                }
    } else {
        price_all(&g, now, run, open);
    }
    ws->was_open = ws->open_wall;
    ws->open_wall = now;
    return closing;
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
 * the wall at each point; and the slack for rounding in reduced times (maze/fastpath/query.py). */
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
    double slack;
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
    double *times;  /* the bound: per node, a lower bound of the time to the goal */
    int32_t *rindptr, *rsrc, *redge, cost;  /* cost: the edges the last find scanned (fp_bound) */
    double *rprice;  /* the prices and open flags in the reversed rows' order: a search back reads them in turn */
    uint8_t *valid_for;
    int has_bound;
    int64_t spent;
    /* decoding */
    int64_t *turn_keys;
    int32_t *turn_key_shape, *offsets, *noffsets, stride[8];
    double unit[8];
    double slack;
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
                     g->run, g->times, g->rindptr, g->rsrc, g->redge, g->valid_for, g->turn_keys,
                     g->turn_key_shape, g->offsets, g->noffsets, g->rprice};
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
    g->slack = s->slack;
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
        g->valid_for = malloc((size_t)g->walls + 1);
        g->rprice = malloc(sizeof(double) * (m + 1));
        ok = by_dst && g->rindptr && g->rsrc && g->times && g->valid_for && g->rprice;
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
    if (ok) {
        edges_t e = {g->outer, g->line_walls, g->line_len, g->line_nodes, g->run_from, g->open_needed, g->turn_walls,
                     g->start_first_wall, g->start_run_from, g->start_open_needed, g->nouter, g->nlines, g->width,
                     g->nstraight, g->before, g->nturns, CROSSINGS, g->nstart, g->layer};
        ok = index_walls(g->ws, &e, g->walls);
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
 * costs: the ski-rental rule of maze/fastpath/bound.py, both counted in the edges they scan, which is what their
 * work per node is, where a count of nodes would weigh a node the find settles as one A* merely forgets); A*
 * resumed from the last query's (`invalidate`) where only walls closed under the same bound, else from scratch;
 * then the exact search. Writes the route's nodes (global numbers, the start first) and times; returns their
 * count, 0 when the goal cannot be reached. */
int32_t fp_query(void *p, const uint8_t *blocked, int32_t *route, double *times) {
    graph_t *g = p;
    workspace *ws = g->ws;
    int closing = fp_price(ws, blocked, g->walls, g->outer, g->nouter, g->line_walls, g->line_len, g->nlines,
                           g->width, g->line_nodes, g->run, g->layer, g->nstraight, g->before, g->run_from,
                           g->open_needed, g->nturns, CROSSINGS, g->turn_walls, g->nstart, g->start_first_wall,
                           g->start_run_from, g->start_open_needed, g->open);
    int stale = !g->has_bound || g->spent > g->cost;
    for (int32_t w = 0; w < g->walls && !stale; w++) stale = g->valid_for[w] > blocked[w];
    if (stale) {
        astar_reset(ws);
        g->cost = fp_bound(ws, g->rindptr, g->rsrc, g->rprice, g->redge, g->indptr, g->indices, g->open,
                           g->goal_nodes, g->ngoals, g->times);
        memcpy(g->valid_for, blocked, (size_t)g->walls);
        g->has_bound = 1, g->spent = 0;
    }
    if (stale || !closing) {
        astar_reset(ws);
    } else {
        g->spent += invalidate(ws, g->indptr, g->indices, g->price, g->times, g->open, g->rindptr, g->rsrc, g->redge,
                               ws->closed, ws->nclosed);
    }
    int32_t length = fp_search(ws, g->indptr, g->indices, g->times, g->price, g->open, g->rindptr, g->rsrc,
                               g->redge, g->goal_lo, g->goal_hi, g->times[g->n - 1], g->slack, &g->spent, route,
                               times);
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
