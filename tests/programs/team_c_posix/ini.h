/* A small INI reader: "[section]" headers, "key = value" lines, ';' or '#' comments. */
#ifndef INI_H
#define INI_H

/* The value of `key` in `section` of the file at `path`, or `fallback`. */
double ini_number(const char *path, const char *section, const char *key, double fallback);

#endif
