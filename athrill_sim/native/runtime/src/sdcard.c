/*
 * The SD card: the program's working directory (the bench starts it in a copy of its workspace, which holds its
 * own sdcard/ folder's contents: athrill_sim/programs/working_folder.py), so that fopen of a relative path and EV3RT's
 * ev3_sdcard_* and ev3_memfile_* see the same files. Argument checks and error
 * codes are EV3RT's (ev3api_fs.c): memfile_load with no path is E_PAR, with no memfile E_NOMEM, a file that
 * does not open E_PAR; memfile_free of NULL E_PAR, of a freed one E_OBJ.
 */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "ev3api.h"
#include "real.h"
#include "runtime.h"

#define MAX_DIRS 16

static DIR *dirs[MAX_DIRS + 1];
static char dir_paths[MAX_DIRS + 1][4096];

ER ev3_memfile_load(const char *path, memfile_t *p_memfile)
{
    if (path == NULL)
        return E_PAR;
    if (p_memfile == NULL)
        return E_NOMEM;
    p_memfile->buffer = NULL;
    FILE *f = hako_real()->fopen(path, "rb");
    if (f == NULL) {
        hako_log("API %s() warning: Path '%s' is invalid.", __func__, path); /* API_WARN */
        return E_PAR;
    }
    long size = fseek(f, 0, SEEK_END) == 0 ? ftell(f) : -1;
    if (size < 0 || fseek(f, 0, SEEK_SET) != 0) {
        fclose(f);
        return E_OBJ;
    }
    void *buffer = malloc(size > 0 ? (size_t)size : 1);
    if (buffer == NULL) {
        fclose(f);
        return E_NOMEM;
    }
    size_t got = fread(buffer, 1, (size_t)size, f);
    fclose(f);
    if (got != (size_t)size) {
        free(buffer);
        return E_PAR;
    }
    *p_memfile = (memfile_t){buffer, (uint32_t)size, (uint32_t)size};
    return E_OK;
}

ER ev3_memfile_free(memfile_t *p_memfile)
{
    if (p_memfile == NULL)
        return E_PAR;
    if (p_memfile->buffer == NULL)
        return E_OBJ;
    free(p_memfile->buffer);
    p_memfile->buffer = NULL;
    return E_OK;
}

ER_ID ev3_sdcard_opendir(const char *path)
{
    if (path == NULL)
        return E_PAR;
    for (ID id = 1; id <= MAX_DIRS; id++) {
        if (dirs[id] != NULL)
            continue;
        dirs[id] = opendir(path);
        if (dirs[id] == NULL)
            return E_PAR;
        snprintf(dir_paths[id], sizeof dir_paths[id], "%s", path);
        return id;
    }
    return E_NOID;
}

ER ev3_sdcard_readdir(ID dirid, fileinfo_t *p_fileinfo)
{
    if (dirid < 1 || dirid > MAX_DIRS || dirs[dirid] == NULL)
        return E_ID;
    if (p_fileinfo == NULL)
        return E_PAR;
    struct dirent *e;
    do {
        e = readdir(dirs[dirid]);
    } while (e != NULL && (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0));
    if (e == NULL)
        return E_OBJ; /* no more entries */
    char path[8192];
    struct stat st;
    snprintf(path, sizeof path, "%s/%s", dir_paths[dirid], e->d_name);
    bool ok = stat(path, &st) == 0;
    memset(p_fileinfo, 0, sizeof *p_fileinfo);
    strncpy(p_fileinfo->name, e->d_name, TMAX_FILENAME_LEN);
    p_fileinfo->size = ok && S_ISREG(st.st_mode) ? (uint32_t)st.st_size : 0;
    p_fileinfo->is_dir = ok && S_ISDIR(st.st_mode);
    p_fileinfo->is_readonly = ok && !(st.st_mode & S_IWUSR);
    p_fileinfo->is_hidden = e->d_name[0] == '.';
    return E_OK;
}

ER ev3_sdcard_closedir(ID dirid)
{
    if (dirid < 1 || dirid > MAX_DIRS || dirs[dirid] == NULL)
        return E_ID;
    closedir(dirs[dirid]);
    dirs[dirid] = NULL;
    return E_OK;
}
