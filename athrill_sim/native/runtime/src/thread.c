/*
 * The program's threads as tasks of the kernel's (scheduler.h): created, ended, joined or detached, and
 * reaped; their numbers, names and keys.
 */
#define _GNU_SOURCE
#include "kernel_impl.h"

hako_task *hako_self(void) { return hako_k.running; }

long hako_task_number(const hako_task *t) { return t != NULL ? t->number : 0; }

hako_task *hako_task_by_number(long number)
{
    return number >= 1 && number <= hako_k.task_count ? hako_k.tasks[number - 1] : NULL;
}

long hako_task_limit(void) { return hako_k.task_count; }

const char *hako_task_name(const hako_task *t) { return t != NULL ? t->name : "the kernel"; }

hako_task *hako_thread_create(void *(*entry)(void *), void *arg, size_t stack_size)
{
    HAKO_SERVICE;
    struct task *t = hako_new_task();
    if (t == NULL)
        return NULL;
    if (!hako_give_stack(t, stack_size > HAKO_THREAD_STACK ? stack_size : HAKO_THREAD_STACK)) {
        hako_k.tasks[--hako_k.task_count] = NULL;
        free(t);
        return NULL;
    }
    snprintf(t->name, sizeof t->name, "thread %ld", t->number);
    t->thread = true;
    t->thread_entry = entry;
    t->thread_arg = arg;
    t->priority = hako_k.running != NULL ? hako_k.running->priority : TMAX_TPRI;
    hako_activate(t);
    return t;
}

void hako_thread_exit(void *result)
{
    HAKO_SERVICE;
    hako_k.running->result = result;
    hako_end_running();
}

bool hako_thread_ended(const hako_task *t, void **result)
{
    if (t->state != ENDED)
        return false;
    if (result != NULL)
        *result = t->result;
    return true;
}

bool hako_thread_is_thread(const hako_task *t) { return t->thread; }

int hako_thread_release(hako_task *t)
{
    if (t->released)
        return EINVAL;
    t->released = true;
    return 0;
}

void **hako_task_specific(hako_task *t, unsigned key)
{
    if (key >= HAKO_KEYS)
        return NULL;
    if (t->specific == NULL && (t->specific = calloc(HAKO_KEYS, sizeof *t->specific)) == NULL)
        return NULL;
    return &t->specific[key];
}

void hako_kernel_forked(void)
{
    HAKO_SERVICE;
    for (long i = 0; i < hako_k.task_count; i++)
        if (hako_k.tasks[i] != NULL && hako_k.tasks[i] != hako_k.running) {
            hako_k.tasks[i]->state = hako_k.tasks[i]->thread ? ENDED : DORMANT;
            hako_k.tasks[i]->activations = 0;
            hako_k.tasks[i]->timed = false;
        }
    for (uint_t i = 0; i < hako_cyclic_count; i++)
        hako_k.cyclics[i].active = false;
}

int hako_tasks_stuck(void)
{
    int stuck = 0;
    for (long i = 0; i < hako_k.task_count; i++)
        if (hako_k.tasks[i] != NULL && hako_k.tasks[i]->state == WAITING && hako_k.tasks[i]->wait == WAIT_OBJECT &&
            !hako_k.tasks[i]->timed)
            stuck++;
    return stuck;
}

/* A thread that ended and was joined or detached: its stack and record go (never while it runs on them). */
void hako_reap(void)
{
    for (long i = 0; i < hako_k.task_count; i++) {
        struct task *t = hako_k.tasks[i];
        if (t == NULL || !t->thread || t->state != ENDED || !t->released)
            continue;
        munmap(t->area, t->area_size);
        free(t->specific);
        free(t);
        hako_k.tasks[i] = NULL;
    }
}
