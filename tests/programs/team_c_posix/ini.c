#include "ini.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static char *trim(char *s)
{
    while (*s == ' ' || *s == '\t')
        s++;
    char *end = s + strlen(s);
    while (end > s && (end[-1] == ' ' || end[-1] == '\t' || end[-1] == '\n' || end[-1] == '\r'))
        *--end = '\0';
    return s;
}

double ini_number(const char *path, const char *section, const char *key, double fallback)
{
    FILE *f = fopen(path, "r");
    if (f == NULL)
        return fallback;
    char line[256], current[64] = "";
    double value = fallback;
    while (fgets(line, sizeof line, f) != NULL) {
        char *s = trim(line);
        if (*s == ';' || *s == '#' || *s == '\0')
            continue;
        if (*s == '[') {
            char *close = strchr(s, ']');
            if (close != NULL) {
                *close = '\0';
                snprintf(current, sizeof current, "%s", trim(s + 1));
            }
            continue;
        }
        char *eq = strchr(s, '=');
        if (eq == NULL || strcmp(current, section) != 0)
            continue;
        *eq = '\0';
        if (strcmp(trim(s), key) == 0)
            value = strtod(eq + 1, NULL);
    }
    fclose(f);
    return value;
}
