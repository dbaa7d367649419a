/*
 * The devices the kernel serves, as hooks: each device module declares its own with HAKO_DEVICE, and the
 * kernel runs every declared one without knowing any by name, so a device module may use the kernel's
 * services without the kernel depending on it. The declarations are collected by the linker into one
 * section (GNU ld's __start_/__stop_ symbols), in link order; a program without SPIKE devices links none.
 */
#ifndef HAKO_DEVICES_H
#define HAKO_DEVICES_H

#include <stdbool.h>
#include <stdint.h>

typedef struct hako_device {
    void (*start)(void); /* when the kernel starts, before the program's objects and tasks; or NULL */
    void (*serve)(void); /* at every snapshot, before any task runs at that instant; or NULL */
    /* The next instant after `tick` it must be served at, waking the kernel if no task would; HAKO_FOREVER
     * when it needs none. NULL: never. */
    int64_t (*next_due)(int64_t tick);
    /* Its next_due wakes the kernel only while a task or handler will run again: a device that only keeps
     * what a program may read up to date, which does not keep a program that has ended alive. */
    bool passive;
} hako_device;

#define HAKO_DEVICE(name)                                                                                              \
    static const hako_device name;                                                                                     \
    __attribute__((used, section("hako_devices"))) static const hako_device *const name##_entry = &name;               \
    static const hako_device name

/* The declared devices, for the kernel. */
extern const hako_device *const __start_hako_devices[] __attribute__((weak));
extern const hako_device *const __stop_hako_devices[] __attribute__((weak));

#endif /* HAKO_DEVICES_H */
