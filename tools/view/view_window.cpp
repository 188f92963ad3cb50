/*
 * The window of `persp view`: SDL2 for the window, input and the streaming
 * texture the frame is shown in, Dear ImGui for panels and text. The
 * images themselves come from persp_render on all of the context's threads
 * (view_core.c); this file only drives them. Controls: docs/VIEWER.md.
 */
#include "view_window.h"

#include "imgui_sdl_draw.h"

#include <SDL.h>
#include <backends/imgui_impl_sdl.h>
#include <imgui.h>

#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <string>
#include <vector>

namespace
{

const char *const font_paths[] = {
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
};

/* One side's choices as the panel edits them; the spec is rebuilt from the
 * method name and its parameter text and checked before it is used. */
struct side_ui {
    int method_index = 0;
    char params[48] = "";
    std::string error;
};

/* What one render is asked to produce. */
struct job {
    view_camera cam;
    view_settings left, right;
    view_layout layout;
    double divider;
    int heat_max, error_stats, w, h;
    unsigned long serial;
};

/* Renders on its own thread (with the context's workers), so the window
 * keeps answering while a slow configuration draws. Two frames: the worker
 * draws into the one that is not `front`; the window copies `front` under
 * the lock. */
struct worker {
    persp_context *ctx = nullptr;
    view_scenes scenes{};
    SDL_Thread *thread = nullptr;
    SDL_mutex *lock = nullptr;
    SDL_cond *wake = nullptr, *done = nullptr;
    bool quit = false, pending = false;
    job next{};
    view_frame frames[2]{};
    int front = -1;
    unsigned long done_serial = 0;
    std::string error; /* of the last job */
};

int worker_main(void *arg)
{
    worker &w = *(worker *)arg;
    SDL_LockMutex(w.lock);
    for (;;) {
        while (!w.pending && !w.quit)
            SDL_CondWait(w.wake, w.lock);
        if (w.quit) break;
        job j = w.next;
        w.pending = false;
        int back = w.front == 0 ? 1 : 0;
        SDL_UnlockMutex(w.lock);
        view_frame &f = w.frames[back];
        std::string err;
        persp_status st = view_frame_resize(&f, j.w, j.h);
        if (st == PERSP_OK)
            st = view_frame_render(w.ctx, &w.scenes, &j.cam, &j.left, &j.right, j.layout, j.divider,
                                   j.heat_max, j.error_stats, &f);
        if (st != PERSP_OK)
            err = std::string(persp_status_string(st)) + ": " + persp_context_error(w.ctx);
        SDL_LockMutex(w.lock);
        if (st == PERSP_OK) w.front = back;
        w.error = err;
        w.done_serial = j.serial;
        SDL_CondBroadcast(w.done);
    }
    SDL_UnlockMutex(w.lock);
    return 0;
}

/* One line of a --script file (docs/VIEWER.md). */
struct action {
    int line;
    std::string op;
    std::vector<std::string> arg;
};

/* Where the replay of a --script file stands. Input actions become SDL
 * events pushed into the queue, so they take the same way as a person's. */
struct script {
    std::vector<action> actions;
    size_t next = 0;
    int wait = 0;            /* frames left before the next action */
    std::vector<std::pair<int, SDL_Event>> later; /* (frames from now, event) */
    int mouse_x = 0, mouse_y = 0;
    std::vector<const action *> shots; /* taken once this frame is drawn */
    bool settling = false;
    long timing_frames = -1; /* frames since `timing start`; -1: not timing */
    double timing_start = 0.0;
};

bool load_script(const char *path, script *sc, std::string *err)
{
    FILE *f = fopen(path, "r");
    if (!f) {
        *err = std::string(path) + ": " + strerror(errno);
        return false;
    }
    char buf[1024];
    int line = 0;
    while (fgets(buf, sizeof buf, f)) {
        line++;
        char *hash = strchr(buf, '#');
        if (hash) *hash = '\0';
        action a;
        a.line = line;
        for (char *t = strtok(buf, " \t\r\n"); t; t = strtok(nullptr, " \t\r\n"))
            (a.op.empty() ? a.op : a.arg.emplace_back()) = t;
        if (a.op.empty()) continue;
        static const struct {
            const char *op;
            size_t lo, hi;
        } known[] = {{"wait", 1, 1},  {"key", 1, 2},   {"hold", 2, 2},   {"method", 2, 2},
                     {"move", 2, 2},  {"drag", 2, 3},  {"play", 1, 1},   {"settle", 0, 0},
                     {"shot", 1, 1},  {"image", 1, 1}, {"scale", 1, 1},  {"timing", 1, 1},
                     {"stats", 1, 1}, {"quit", 0, 0}};
        bool ok = false;
        for (const auto &k : known)
            if (a.op == k.op) ok = a.arg.size() >= k.lo && a.arg.size() <= k.hi;
        if (ok && (a.op == "key" || a.op == "hold") &&
            SDL_GetKeyFromName(a.arg[0].c_str()) == SDLK_UNKNOWN)
            ok = false;
        if (ok && a.op == "method")
            ok = (a.arg[0] == "left" || a.arg[0] == "right") &&
                 persp_method_check(a.arg[1].c_str()) == PERSP_OK;
        if (ok && a.op == "timing") ok = a.arg[0] == "start" || a.arg[0] == "stop";
        if (ok && a.op == "stats") ok = a.arg[0] == "on" || a.arg[0] == "off";
        if (ok && (a.op == "wait" || a.op == "key" || a.op == "hold" || a.op == "move" ||
                   a.op == "drag" || a.op == "scale"))
            for (size_t i = a.op == "key" || a.op == "hold" ? 1 : 0; i < a.arg.size(); i++) {
                char *end;
                double v = strtod(a.arg[i].c_str(), &end);
                ok = ok && *end == '\0' && v >= 0 && v <= 1e6;
            }
        if (!ok) {
            *err = std::string(path) + ":" + std::to_string(line) + ": cannot read '" + a.op;
            for (const auto &x : a.arg)
                *err += " " + x;
            *err += "'";
            fclose(f);
            return false;
        }
        sc->actions.push_back(a);
    }
    fclose(f);
    return true;
}

struct state {
    const view_window_args *args;
    persp_context *ui_ctx = nullptr; /* the window's own (PNG writes), the worker has args->ctx */
    worker wk;
    unsigned long serial = 0, shown_serial = 0;
    SDL_Window *window = nullptr;
    SDL_Renderer *renderer = nullptr;
    SDL_Texture *texture = nullptr;
    int tex_w = 0, tex_h = 0;

    view_camera cam{}, home{};
    view_settings left{}, right{};
    side_ui ui[2];
    bool right_follows = true;
    view_layout layout = VIEW_LAYOUT_SPLIT;
    double divider = 0.5;
    int heat_max = 16;
    bool error_stats = true;
    bool orbit = false;
    double speed = 2.0; /* scene units per second */
    float move_scale = 0.5f;
    bool magnifier = false;
    int mag_cells = 15, mag_px = 10;
    bool panel = true;

    view_frame frame{};
    bool have_frame = false;
    std::string render_error;
    /* What the last frame was rendered with, to render only on change. */
    std::vector<unsigned char> last_key;

    double last_motion = -1.0; /* time of the last camera change */
    bool dragging_divider = false, turning = false;
    int mouse_x = -1,
        mouse_y = -1; /* from the events: SDL's own state is not kept for synthetic ones */
    double now = 0.0;

    bool recording = false;
    double record_start = 0.0;
    view_path recorded{};
    const view_path *playing = nullptr;
    double play_start = 0.0;

    /* Held keys from the events (SDL's keyboard state misses pushed ones). */
    bool held[SDL_NUM_SCANCODES] = {};
    script sc;
    bool scripted = false;
    bool overlay = false; /* split layout: differing pixels as heat colours, with a legend */
    bool reupload = false;
    view_path script_path{};

    std::string status; /* the last message (screenshot written, path saved) */
    int shots = 0;
    double fps = 0.0;
};

double seconds()
{
    return (double)SDL_GetPerformanceCounter() / (double)SDL_GetPerformanceFrequency();
}

size_t method_count()
{
    return persp_method_count();
}

const char *method_name(size_t i)
{
    persp_method_info info;
    return persp_method_get(i, &info) == PERSP_OK ? info.name : "?";
}

/* Splits "name:params" into the panel's fields. */
void side_from_spec(side_ui *ui, const char *spec)
{
    const char *colon = strchr(spec, ':');
    size_t len = colon ? (size_t)(colon - spec) : strlen(spec);
    ui->method_index = 0;
    for (size_t i = 0; i < method_count(); i++)
        if (strlen(method_name(i)) == len && !strncmp(method_name(i), spec, len))
            ui->method_index = (int)i;
    snprintf(ui->params, sizeof ui->params, "%s", colon ? colon + 1 : "");
}

void update_spec(side_ui *ui, view_settings *s)
{
    char spec[64];
    const char *name = method_name((size_t)ui->method_index);
    if (ui->params[0])
        snprintf(spec, sizeof spec, "%s:%s", name, ui->params);
    else
        snprintf(spec, sizeof spec, "%s", name);
    if (persp_method_check(spec) == PERSP_OK) {
        snprintf(s->method, sizeof s->method, "%s", spec);
        ui->error.clear();
    } else {
        persp_method_info info;
        persp_method_get((size_t)ui->method_index, &info);
        ui->error = std::string("bad parameters; expected ") + info.params;
    }
}

template <typename E>
bool enum_combo(const char *label, E *value, int first, int last, const char *(*name)(int))
{
    int v = (int)*value;
    bool changed = false;
    if (ImGui::BeginCombo(label, name(v))) {
        for (int i = first; i <= last; i++)
            if (ImGui::Selectable(name(i), i == v)) v = i, changed = true;
        ImGui::EndCombo();
    }
    if (changed) *value = (E)v;
    return changed;
}

const char *filter_label(int v)
{
    return persp_filter_name((persp_filter)v);
}
const char *wrap_label(int v)
{
    return persp_wrap_name((persp_wrap)v);
}
const char *shading_label(int v)
{
    return persp_shading_name((persp_shading)v);
}
const char *depth_label(int v)
{
    return v == 0 ? "default" : v == 1 ? "z" : "1/w";
}
const char *lod_label(int v)
{
    return v == 0 ? "default" : v == 1 ? "pixel" : "polygon";
}
const char *pipeline_label(int v)
{
    return v == 0 ? "default" : v == 1 ? "screen" : "object";
}
const char *layout_label(int v)
{
    return v == 0 ? "single" : v == 1 ? "split" : v == 2 ? "colour difference" : "texel difference";
}

void mip_legend()
{
    ImDrawList *dl = ImGui::GetWindowDrawList();
    for (int l = 0; l < 10; l++) {
        uint8_t c[4];
        persp_mip_level_color(l, c);
        ImVec2 p = ImGui::GetCursorScreenPos();
        dl->AddRectFilled(p, ImVec2(p.x + 22, p.y + 16), IM_COL32(c[0], c[1], c[2], 255));
        char t[8];
        snprintf(t, sizeof t, l == 9 ? "9+" : "%d", l);
        dl->AddText(ImVec2(p.x + 5, p.y + 1), IM_COL32(0, 0, 0, 255), t);
        ImGui::Dummy(ImVec2(24, 16));
        if (l < 9) ImGui::SameLine(0, 2);
    }
}

void settings_panel(const char *id, side_ui *ui, view_settings *s, bool with_ops)
{
    ImGui::PushID(id);
    int mi = ui->method_index;
    if (ImGui::BeginCombo("method", method_name((size_t)mi))) {
        for (size_t i = 0; i < method_count(); i++)
            if (ImGui::Selectable(method_name(i), (int)i == mi)) {
                ui->method_index = (int)i;
                ui->params[0] = '\0';
            }
        ImGui::EndCombo();
    }
    persp_method_info info;
    persp_method_get((size_t)ui->method_index, &info);
    if (info.params[0]) {
        ImGui::InputTextWithHint("parameters", info.params, ui->params, sizeof ui->params);
    } else {
        ui->params[0] = '\0';
    }
    update_spec(ui, s);
    if (!ui->error.empty()) ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", ui->error.c_str());
    if (ImGui::IsItemHovered() || ImGui::IsItemActive()) ImGui::SetTooltip("%s", info.summary);
    ImGui::TextDisabled("%s", info.cost);
    enum_combo("filter", &s->filter, 0, PERSP_FILTER_COUNT - 1, filter_label);
    if (s->filter == PERSP_FILTER_ANISO || s->filter == PERSP_FILTER_ANISO_WINDOW) {
        if (s->max_aniso < 1) s->max_aniso = PERSP_MAX_ANISO;
        ImGui::SliderInt("max aniso", &s->max_aniso, 1, PERSP_MAX_ANISO);
    }
    enum_combo("wrap", &s->wrap, 0, PERSP_WRAP_CLAMP_TO_BORDER, wrap_label);
    enum_combo("shading", &s->shading, 0, PERSP_SHADING_COUNT - 1, shading_label);
    enum_combo("depth", &s->depth, 0, PERSP_DEPTH_INVW, depth_label);
    enum_combo("LOD", &s->lod, 0, PERSP_LOD_POLYGON, lod_label);
    ImGui::SliderFloat("LOD bias", &s->lod_bias, -4.0f, 4.0f, "%.2f");
    enum_combo("pipeline", &s->pipeline, 0, PERSP_PIPELINE_OBJECT, pipeline_label);
    bool mip = s->mip_levels != 0;
    if (ImGui::Checkbox("mip levels as colours", &mip)) s->mip_levels = mip;
    if (mip) mip_legend();
    if (with_ops) {
        bool ops = s->count_ops != 0;
        if (ImGui::Checkbox("count operations (slower)", &ops)) s->count_ops = ops;
    }
    ImGui::PopID();
}

void heat_legend(int heat_max, bool texel)
{
    ImDrawList *dl = ImGui::GetWindowDrawList();
    ImVec2 p = ImGui::GetCursorScreenPos();
    float w = ImGui::GetContentRegionAvail().x, h = 14.0f;
    const int steps = 64;
    for (int i = 0; i < steps; i++) {
        double d = (double)heat_max * ((double)i + 0.5) / steps;
        uint8_t rgb[3];
        view_heat_color(i == 0 ? 0.0 : d, heat_max, rgb);
        dl->AddRectFilled(ImVec2(p.x + w * (float)i / steps, p.y),
                          ImVec2(p.x + w * (float)(i + 1) / steps, p.y + h),
                          IM_COL32(rgb[0], rgb[1], rgb[2], 255));
    }
    ImGui::Dummy(ImVec2(w, h));
    ImGui::Text("0");
    ImGui::SameLine(w * 0.5f);
    ImGui::Text("%g", heat_max / 4.0); /* square-root scale: the middle is a quarter */
    ImGui::SameLine(w - 30.0f);
    ImGui::Text(">=%d", heat_max);
    if (texel)
        ImGui::TextDisabled("distance of the texels the two sides' texture\n"
                            "coordinates fall in, in texels of a %dx%d texture\n"
                            "(nearest filter, no shading); grey: equal",
                            VIEW_COORD_SIZE, VIEW_COORD_SIZE);
    else
        ImGui::TextDisabled("largest RGB difference per pixel, in levels;\n"
                            "equal pixels show the left image dimmed");
}

void screenshot(state &s)
{
    if (!s.have_frame) return;
    if (view_make_dirs(s.args->shot_dir) != 0) {
        s.status = std::string("cannot create ") + s.args->shot_dir + ": " + strerror(errno);
        return;
    }
    char path[4096];
    do {
        snprintf(path, sizeof path, "%s/view_%04d.png", s.args->shot_dir, s.shots++);
    } while (access(path, F_OK) == 0 && s.shots < 10000);
    persp_image img = {s.frame.width, s.frame.height, (size_t)s.frame.width * 4, s.frame.out};
    persp_status st = persp_image_write_png(s.ui_ctx, path, &img);
    s.status = st == PERSP_OK ? std::string("wrote ") + path
                              : std::string(path) + ": " + persp_context_error(s.ui_ctx);
}

/* What the window shows, panels included (the renderer's read-back). */
void window_shot(state &s, const char *path)
{
    int w, h;
    SDL_GetRendererOutputSize(s.renderer, &w, &h);
    std::vector<uint8_t> top_down((size_t)w * (size_t)h * 4), rows((size_t)w * (size_t)h * 4);
    if (SDL_RenderReadPixels(s.renderer, nullptr, SDL_PIXELFORMAT_RGBA32, top_down.data(), w * 4) !=
        0) {
        s.status = std::string("cannot read the window back: ") + SDL_GetError();
        return;
    }
    for (int y = 0; y < h; y++)
        memcpy(&rows[(size_t)y * (size_t)w * 4], &top_down[(size_t)(h - 1 - y) * (size_t)w * 4],
               (size_t)w * 4);
    persp_image img = {w, h, (size_t)w * 4, rows.data()};
    persp_status st = persp_image_write_png(s.ui_ctx, path, &img);
    s.status = st == PERSP_OK ? std::string("wrote ") + path
                              : std::string(path) + ": " + persp_context_error(s.ui_ctx);
}

void toggle_recording(state &s)
{
    if (!s.recording) {
        view_path_free(&s.recorded);
        s.recording = true;
        s.record_start = s.now;
        s.playing = nullptr;
        s.status = "recording";
        return;
    }
    s.recording = false;
    char err[512];
    if (s.recorded.count && view_path_save(s.args->record_path, &s.recorded, err, sizeof err))
        s.status = std::string("saved ") + std::to_string(s.recorded.count) + " keys to " +
                   s.args->record_path;
    else
        s.status = s.recorded.count ? err : "nothing recorded";
}

void start_playing(state &s, const view_path *p)
{
    if ((!p || !p->count) && access(s.args->record_path, R_OK) == 0) {
        /* Nothing recorded in this session: the flight saved last time. */
        char err[512];
        view_path loaded;
        if (view_path_load(s.args->record_path, &loaded, err, sizeof err)) {
            view_path_free(&s.recorded);
            s.recorded = loaded;
            p = &s.recorded;
        } else {
            s.status = err;
            return;
        }
    }
    if (!p || !p->count) {
        s.status = "no camera path to play (record one first)";
        return;
    }
    s.recording = false;
    s.playing = p;
    s.play_start = s.now;
}

void camera_changed(state &s)
{
    s.last_motion = s.now;
}

/* Render size: the window's, scaled down while the camera moves. */
void render_size(const state &s, int out_w, int out_h, int *w, int *h)
{
    bool moving = s.now - s.last_motion < 0.25 || s.turning || s.playing;
    float k = moving ? s.move_scale : 1.0f;
    *w = (int)((float)out_w * k);
    *h = (int)((float)out_h * k);
    if (*w < 1) *w = 1;
    if (*h < 1) *h = 1;
}

void append_key(std::vector<unsigned char> &key, const void *p, size_t n)
{
    const unsigned char *b = (const unsigned char *)p;
    key.insert(key.end(), b, b + n);
}

bool rendering(state &s)
{
    SDL_LockMutex(s.wk.lock);
    bool busy = s.wk.done_serial != s.serial;
    SDL_UnlockMutex(s.wk.lock);
    return busy;
}

/* Asks for a render when anything it depends on changed, and takes over a
 * finished one. wait: block until the latest request is done. */
void upload(state &s);

void render_if_needed(state &s, int w, int h, bool wait)
{
    std::vector<unsigned char> key;
    append_key(key, &s.cam, sizeof s.cam);
    append_key(key, &s.left, sizeof s.left);
    append_key(key, &s.right, sizeof s.right);
    append_key(key, &s.layout, sizeof s.layout);
    append_key(key, &s.divider, sizeof s.divider);
    append_key(key, &s.heat_max, sizeof s.heat_max);
    append_key(key, &s.error_stats, sizeof s.error_stats);
    append_key(key, &w, sizeof w);
    append_key(key, &h, sizeof h);
    worker &wk = s.wk;
    SDL_LockMutex(wk.lock);
    if (key != s.last_key) {
        s.last_key = key;
        wk.next = job{s.cam,      s.left,        s.right, s.layout, s.divider,
                      s.heat_max, s.error_stats, w,       h,        ++s.serial};
        wk.pending = true;
        SDL_CondSignal(wk.wake);
    }
    while (wait && wk.done_serial != s.serial)
        SDL_CondWait(wk.done, wk.lock);
    bool updated = false;
    if (wk.done_serial != s.shown_serial) {
        s.shown_serial = wk.done_serial;
        s.render_error = wk.error;
        if (wk.error.empty() && wk.front >= 0) {
            const view_frame &src = wk.frames[wk.front];
            if (view_frame_resize(&s.frame, src.width, src.height) == PERSP_OK) {
                size_t n = (size_t)src.width * (size_t)src.height * 4;
                memcpy(s.frame.left, src.left, n);
                memcpy(s.frame.right, src.right, n);
                memcpy(s.frame.out, src.out, n);
                memcpy(s.frame.stats, src.stats, sizeof src.stats);
                memcpy(s.frame.ms, src.ms, sizeof src.ms);
                s.frame.err = src.err;
                s.frame.have_err = src.have_err;
                s.frame.layout = src.layout;
                updated = true;
            } else {
                s.render_error = "out of memory";
            }
        }
    }
    SDL_UnlockMutex(wk.lock);
    if (updated || s.reupload) upload(s);
}

/* The frame into the streaming texture; the difference overlay is applied
 * here so that toggling it needs no render. */
void upload(state &s)
{
    s.reupload = false;
    if (!s.frame.out) return;
    int w = s.frame.width, h = s.frame.height;
    if (!s.texture || s.tex_w != w || s.tex_h != h) {
        if (s.texture) SDL_DestroyTexture(s.texture);
        s.texture = SDL_CreateTexture(s.renderer, SDL_PIXELFORMAT_RGBA32,
                                      SDL_TEXTUREACCESS_STREAMING, w, h);
        s.tex_w = w, s.tex_h = h;
    }
    void *pixels;
    int pitch;
    if (s.texture && SDL_LockTexture(s.texture, nullptr, &pixels, &pitch) == 0) {
        /* persp's rows go bottom-up, SDL's top-down. */
        bool heat = s.overlay && s.frame.layout == VIEW_LAYOUT_SPLIT && s.frame.have_err;
        for (int y = 0; y < h; y++) {
            unsigned char *dst = (unsigned char *)pixels + (size_t)y * (size_t)pitch;
            size_t row = (size_t)(h - 1 - y) * (size_t)w * 4;
            memcpy(dst, s.frame.out + row, (size_t)w * 4);
            if (!heat) continue;
            for (int x = 0; x < w; x++) {
                const uint8_t *a = s.frame.left + row + (size_t)x * 4,
                              *b = s.frame.right + row + (size_t)x * 4;
                int d = 0;
                for (int c = 0; c < 3; c++)
                    d = std::max(d, abs((int)a[c] - (int)b[c]));
                if (d) view_heat_color(d, s.heat_max, dst + (size_t)x * 4);
            }
        }
        SDL_UnlockTexture(s.texture);
    }
    s.have_frame = true;
}

void hud(state &s, int out_w)
{
    /* A narrow window starts with the panel folded into a title bar across
     * the top (panel()): the HUD goes below it, and its lines wrap at the
     * window's edge instead of running past it. */
    const ImGuiIO &io = ImGui::GetIO();
    const bool narrow = io.DisplaySize.x < 900.0f;
    ImGui::SetNextWindowPos(ImVec2(8, narrow && s.panel ? 14 + ImGui::GetFrameHeight() : 8), ImGuiCond_Always);
    ImGui::SetNextWindowBgAlpha(0.6f);
    ImGui::Begin("hud", nullptr,
                 ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                     ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing |
                     ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoMove);
    ImGui::PushTextWrapPos(io.DisplaySize.x - 24.0f);
    const view_frame &f = s.frame;
    ImGui::Text("%.0f fps   render %dx%d%s", s.fps, f.width, f.height,
                f.width < out_w ? " (reduced while moving)" : "");
    double px = (double)f.width * f.height;
    ImGui::Text("left %-22s %6.1f ms  %6.1f Mpixels/s",
                s.left.method[0] ? s.left.method : "(scene's)", f.ms[0],
                f.ms[0] > 0 ? px / (f.ms[0] * 1e3) : 0.0);
    if (f.have_err)
        ImGui::Text("right %-21s %6.1f ms  %6.1f Mpixels/s", s.right.method, f.ms[1],
                    f.ms[1] > 0 ? px / (f.ms[1] * 1e3) : 0.0);
    const persp_render_stats &st = f.stats[0];
    ImGui::Text("triangles %llu in, %llu drawn; %llu fragments",
                (unsigned long long)st.triangles_in, (unsigned long long)st.triangles_drawn,
                (unsigned long long)st.fragments);
    if (s.left.count_ops) {
        /* Per pixel the method computed, as `persp render --count-ops`. */
        double px_done = st.ops.pixels ? (double)st.ops.pixels : 1.0;
        ImGui::Text("left method per pixel: %.2f div  %.2f mul  %.2f add  %.2f cmp",
                    (double)st.ops.div / px_done, (double)st.ops.mul / px_done, (double)st.ops.add / px_done,
                    (double)st.ops.cmp / px_done);
        ImGui::Text("  %.2f px per span; %llu spans", st.ops.spans ? (double)st.ops.pixels / (double)st.ops.spans : 0.0,
                    (unsigned long long)st.ops.spans);
    }
    if (f.have_err && f.layout == VIEW_LAYOUT_TEXEL) {
        ImGui::Text("texel error (of %dx%d): max %.2f, mean %.3f where the sides differ, %.2f%% of "
                    "pixels differ",
                    VIEW_COORD_SIZE, VIEW_COORD_SIZE, f.err.texel_max, f.err.texel_mean,
                    f.err.share_diff * 100.0);
    } else if (f.have_err) {
        if (f.err.max == 0)
            ImGui::Text("left vs right: identical");
        else
            ImGui::Text(
                "left vs right: max %d levels, mean %.3f, %.2f%% of pixels differ, PSNR %.2f dB",
                f.err.max, f.err.mean, f.err.share_diff * 100.0, f.err.psnr);
    }
    double e[3];
    for (int i = 0; i < 3; i++)
        e[i] = s.cam.eye[i] + 0.0; /* no "-0.00" */
    ImGui::TextDisabled("%s camera  eye (%.2f, %.2f, %.2f)  yaw %.1f  pitch %.1f  fov %.1f",
                        s.orbit ? "orbit" : "fly", e[0], e[1], e[2], s.cam.yaw, s.cam.pitch,
                        s.cam.fovy);
    if (rendering(s)) ImGui::TextColored(ImVec4(1, 0.8f, 0.3f, 1), "rendering...");
    if (s.recording) ImGui::TextColored(ImVec4(1, 0.3f, 0.3f, 1), "REC %zu keys", s.recorded.count);
    if (s.playing) ImGui::TextColored(ImVec4(0.4f, 1, 0.4f, 1), "playing camera path");
    if (!s.render_error.empty())
        ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", s.render_error.c_str());
    if (!s.status.empty()) ImGui::TextDisabled("%s", s.status.c_str());
    ImGui::PopTextWrapPos();
    ImGui::End();
}

/* The panel's camera settings. */
static void camera_section(state &s)
{
    int mode = s.orbit ? 1 : 0;
    if (ImGui::RadioButton("fly", mode == 0)) s.orbit = false;
    ImGui::SameLine();
    if (ImGui::RadioButton("orbit", mode == 1)) {
        if (!s.orbit) view_camera_set_orbit(&s.cam, s.cam.orbit_dist);
        s.orbit = true;
    }
    ImGui::SameLine();
    if (ImGui::Button("reset (R)")) s.cam = s.home, camera_changed(s);
    float fov = (float)s.cam.fovy, zn = (float)s.cam.znear;
    if (ImGui::SliderFloat("field of view", &fov, 5.0f, 150.0f, "%.1f deg"))
        s.cam.fovy = fov, s.cam.scene_own = 0, camera_changed(s);
    if (ImGui::SliderFloat("near plane", &zn, 0.001f, 10.0f, "%.3f",
                           ImGuiSliderFlags_Logarithmic)) {
        s.cam.znear = zn;
        if (s.cam.zfar <= zn) s.cam.zfar = zn * 1000.0;
        s.cam.scene_own = 0, camera_changed(s);
    }
    float sp = (float)s.speed;
    if (ImGui::SliderFloat("fly speed", &sp, 0.05f, 100.0f, "%.2f /s",
                           ImGuiSliderFlags_Logarithmic))
        s.speed = sp;
    ImGui::SliderFloat("scale while moving", &s.move_scale, 0.125f, 1.0f, "%.3f");
}

/* The right side: its method over the left's settings, or settings of its own. */
static void right_section(state &s)
{
    ImGui::Checkbox("same settings as left except the method", &s.right_follows);
    if (s.right_follows) {
        ImGui::PushID("rightm");
        side_ui &ui = s.ui[1];
        if (ImGui::BeginCombo("method", method_name((size_t)ui.method_index))) {
            for (size_t i = 0; i < method_count(); i++)
                if (ImGui::Selectable(method_name(i), (int)i == ui.method_index))
                    ui.method_index = (int)i, ui.params[0] = '\0';
            ImGui::EndCombo();
        }
        persp_method_info info;
        persp_method_get((size_t)ui.method_index, &info);
        if (info.params[0])
            ImGui::InputTextWithHint("parameters", info.params, ui.params, sizeof ui.params);
        else
            ui.params[0] = '\0';
        update_spec(&ui, &s.right);
        if (!ui.error.empty())
            ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", ui.error.c_str());
        ImGui::PopID();
    } else {
        settings_panel("right", &s.ui[1], &s.right, false);
    }
}

void panel(state &s)
{
    ImGuiIO &io = ImGui::GetIO();
    /* The panel is for changing settings, the image for looking at: at the
     * default 1024x768 it covers under a sixth of the image (PANEL_W by
     * PANEL_H_SHARE of the height; it was 380 by the full height, 37 %), with
     * the camera and capture sections folded; it scrolls, folds to its title
     * bar (double-click) and F1 hides it. */
    const float PANEL_W = 300.0f, PANEL_H_SHARE = 0.55f;
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - PANEL_W - 8, 8), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(PANEL_W, io.DisplaySize.y * PANEL_H_SHARE), ImGuiCond_FirstUseEver);
    /* A small window keeps its image visible: the panel starts folded. */
    ImGui::SetNextWindowCollapsed(io.DisplaySize.x < 900.0f, ImGuiCond_FirstUseEver);
    ImGui::Begin("persp view  (F1 hides)", &s.panel);
    /* In the narrower panel the labels keep 110 pixels beside the widgets. */
    ImGui::PushItemWidth(-110.0f);
    if (ImGui::CollapsingHeader("Camera")) camera_section(s);
    if (ImGui::CollapsingHeader("View", ImGuiTreeNodeFlags_DefaultOpen)) {
        enum_combo("layout (Tab)", &s.layout, 0, 3, layout_label);
        float d = (float)s.divider;
        if (s.layout == VIEW_LAYOUT_SPLIT && ImGui::SliderFloat("divider", &d, 0.0f, 1.0f, "%.2f"))
            s.divider = d;
        bool stats = s.error_stats;
        if (ImGui::Checkbox("error statistics (both sides)", &stats))
            s.error_stats = stats;
        if (s.layout == VIEW_LAYOUT_DIFF || s.layout == VIEW_LAYOUT_TEXEL) {
            bool texel = s.layout == VIEW_LAYOUT_TEXEL;
            ImGui::SliderInt("hottest at", &s.heat_max, 1, 255, texel ? "%d texels" : "%d levels");
            heat_legend(s.heat_max, texel);
        }
        if (s.layout == VIEW_LAYOUT_SPLIT &&
            ImGui::Checkbox("difference overlay (H)", &s.overlay))
            s.reupload = true;
        ImGui::Checkbox("magnifier (M)", &s.magnifier);
        if (s.magnifier) ImGui::SliderInt("magnified pixels", &s.mag_cells, 5, 41);
    }
    if (ImGui::CollapsingHeader("Left", ImGuiTreeNodeFlags_DefaultOpen))
        settings_panel("left", &s.ui[0], &s.left, true);
    if (ImGui::CollapsingHeader("Right (reference)", ImGuiTreeNodeFlags_DefaultOpen)) right_section(s);
    if (ImGui::CollapsingHeader("Capture")) {
        if (ImGui::Button("screenshot (P)")) screenshot(s);
        ImGui::SameLine();
        if (ImGui::Button(s.recording ? "stop recording (F5)" : "record flight (F5)"))
            toggle_recording(s);
        ImGui::SameLine();
        if (ImGui::Button("play (F6)"))
            start_playing(s, s.recorded.count ? &s.recorded : s.args->play);
        ImGui::TextDisabled("screenshots: %s/\nflight: %s", s.args->shot_dir, s.args->record_path);
    }
    ImGui::PopItemWidth();
    ImGui::End();
    if (s.right_follows) {
        /* The reference keeps its method and its real textures. */
        char m[sizeof s.right.method];
        memcpy(m, s.right.method, sizeof m);
        int mip = s.right.mip_levels;
        s.right = s.left;
        memcpy(s.right.method, m, sizeof m);
        s.right.mip_levels = mip;
        s.right.count_ops = 0;
    }
}

/* The pixels under the cursor, enlarged, with the pixel grid. */
void magnifier(state &s, int out_w, int out_h)
{
    if (!s.magnifier || !s.have_frame) return;
    int mx = s.mouse_x, my = s.mouse_y;
    if (mx < 0) return;
    int win_w, win_h;
    SDL_GetWindowSize(s.window, &win_w, &win_h);
    const view_frame &f = s.frame;
    int cx = (int)((double)mx * f.width / (win_w > 0 ? win_w : 1));
    int cy = f.height - 1 - (int)((double)my * f.height / (win_h > 0 ? win_h : 1));
    int n = s.mag_cells | 1, half = n / 2, cell = s.mag_px;
    ImDrawList *dl = ImGui::GetForegroundDrawList();
    float side = (float)(n * cell);
    float x0 = (float)mx + 24.0f, y0 = (float)my + 24.0f;
    if (x0 + side > (float)out_w) x0 = (float)mx - 24.0f - side;
    if (y0 + side + 40.0f > (float)out_h) y0 = (float)my - 24.0f - side - 40.0f;
    dl->AddRectFilled(ImVec2(x0 - 2, y0 - 2), ImVec2(x0 + side + 2, y0 + side + 40),
                      IM_COL32(20, 20, 20, 230));
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            int px = cx - half + i, py = cy + half - j;
            ImU32 col = IM_COL32(0, 0, 0, 255);
            if (px >= 0 && py >= 0 && px < f.width && py < f.height) {
                const uint8_t *p = f.out + ((size_t)py * (size_t)f.width + (size_t)px) * 4;
                col = IM_COL32(p[0], p[1], p[2], 255);
            }
            ImVec2 a(x0 + (float)(i * cell), y0 + (float)(j * cell));
            dl->AddRectFilled(a, ImVec2(a.x + (float)cell, a.y + (float)cell), col);
        }
    for (int k = 0; k <= n; k++) {
        float t = (float)(k * cell);
        dl->AddLine(ImVec2(x0 + t, y0), ImVec2(x0 + t, y0 + side), IM_COL32(60, 60, 60, 255));
        dl->AddLine(ImVec2(x0, y0 + t), ImVec2(x0 + side, y0 + t), IM_COL32(60, 60, 60, 255));
    }
    ImVec2 c(x0 + (float)(half * cell), y0 + (float)(half * cell));
    dl->AddRect(c, ImVec2(c.x + (float)cell, c.y + (float)cell), IM_COL32(255, 255, 255, 255), 0, 0,
                2.0f);
    if (cx >= 0 && cy >= 0 && cx < f.width && cy < f.height) {
        size_t o = ((size_t)cy * (size_t)f.width + (size_t)cx) * 4;
        char line[160];
        const uint8_t *l = f.left + o, *r = f.right + o;
        snprintf(line, sizeof line, "(%d, %d)  L %3d %3d %3d", cx, cy, l[0], l[1], l[2]);
        dl->AddText(ImVec2(x0, y0 + side + 4), IM_COL32(255, 255, 255, 255), line);
        if (f.have_err) {
            snprintf(line, sizeof line, "          R %3d %3d %3d", r[0], r[1], r[2]);
            dl->AddText(ImVec2(x0, y0 + side + 20), IM_COL32(255, 255, 255, 255), line);
        }
    }
}

void label(ImDrawList *dl, ImVec2 at, const char *text)
{
    ImVec2 size = ImGui::CalcTextSize(text);
    dl->AddRectFilled(ImVec2(at.x - 3, at.y - 1), ImVec2(at.x + size.x + 3, at.y + size.y + 1),
                      IM_COL32(0, 0, 0, 160));
    dl->AddText(at, IM_COL32(255, 255, 255, 255), text);
}

void side_label(const view_settings &v, const char *fallback, char *buf, size_t size)
{
    snprintf(buf, size, "%s%s", v.method[0] ? v.method : fallback,
             v.mip_levels ? " (mip levels)" : "");
}

void overlay(state &s, int out_w, int out_h)
{
    if (s.layout != VIEW_LAYOUT_SPLIT) return;
    ImDrawList *dl = ImGui::GetForegroundDrawList();
    float x = (float)(s.divider * out_w);
    dl->AddLine(ImVec2(x, 0), ImVec2(x, (float)out_h), IM_COL32(255, 255, 255, 200), 2.0f);
    char l[96], r[96];
    side_label(s.left, "scene's method", l, sizeof l);
    side_label(s.right, "exact", r, sizeof r);
    label(dl, ImVec2(x - 8 - ImGui::CalcTextSize(l).x, (float)out_h - 24), l);
    label(dl, ImVec2(x + 8, (float)out_h - 24), r);
    if (!s.overlay) return;
    /* The legend of the overlay, bottom left above the side labels. */
    const float lw = 260.0f, lh = 14.0f, x0 = 8.0f, y0 = (float)out_h - 84.0f;
    dl->AddRectFilled(ImVec2(x0 - 4, y0 - 22), ImVec2(x0 + lw + 4, y0 + lh + 22),
                      IM_COL32(0, 0, 0, 200));
    dl->AddText(ImVec2(x0, y0 - 19), IM_COL32(255, 255, 255, 255),
                "left vs right, levels (H hides)");
    const int steps = 64;
    for (int i = 0; i < steps; i++) {
        uint8_t rgb[3];
        view_heat_color(i == 0 ? 0.0 : s.heat_max * (i + 0.5) / steps, s.heat_max, rgb);
        dl->AddRectFilled(ImVec2(x0 + lw * (float)i / steps, y0),
                          ImVec2(x0 + lw * (float)(i + 1) / steps, y0 + lh),
                          IM_COL32(rgb[0], rgb[1], rgb[2], 255));
    }
    char hi[16];
    snprintf(hi, sizeof hi, ">=%d", s.heat_max);
    dl->AddText(ImVec2(x0, y0 + lh + 2), IM_COL32(255, 255, 255, 255), "1");
    dl->AddText(ImVec2(x0 + lw - ImGui::CalcTextSize(hi).x, y0 + lh + 2),
                IM_COL32(255, 255, 255, 255), hi);
}

void handle_event(state &s, const SDL_Event &e, bool *quit, int out_w)
{
    ImGuiIO &io = ImGui::GetIO();
    switch (e.type) {
    case SDL_QUIT:
        *quit = true;
        break;
    case SDL_WINDOWEVENT:
        if (e.window.event == SDL_WINDOWEVENT_CLOSE) *quit = true;
        break;
    case SDL_KEYUP:
        if (e.key.keysym.scancode < SDL_NUM_SCANCODES) s.held[e.key.keysym.scancode] = false;
        break;
    case SDL_KEYDOWN:
        if (io.WantCaptureKeyboard || e.key.repeat) break;
        if (e.key.keysym.scancode < SDL_NUM_SCANCODES) s.held[e.key.keysym.scancode] = true;
        switch (e.key.keysym.sym) {
        case SDLK_ESCAPE:
            *quit = true;
            break;
        case SDLK_F1:
            s.panel = !s.panel;
            break;
        case SDLK_r:
            s.cam = s.home, camera_changed(s);
            break;
        case SDLK_o:
            s.orbit = !s.orbit;
            if (s.orbit) view_camera_set_orbit(&s.cam, s.cam.orbit_dist);
            break;
        case SDLK_TAB:
            s.layout = (view_layout)((s.layout + 1) % 4);
            break;
        case SDLK_m:
            s.magnifier = !s.magnifier;
            break;
        case SDLK_h:
            s.overlay = !s.overlay, s.reupload = true;
            break;
        case SDLK_p:
        case SDLK_F12:
            screenshot(s);
            break;
        case SDLK_F5:
            toggle_recording(s);
            break;
        case SDLK_F6:
            start_playing(s, s.recorded.count ? &s.recorded : s.args->play);
            break;
        case SDLK_LEFTBRACKET:
            s.cam.fovy = fmax(5.0, s.cam.fovy - 5.0), s.cam.scene_own = 0, camera_changed(s);
            break;
        case SDLK_RIGHTBRACKET:
            s.cam.fovy = fmin(150.0, s.cam.fovy + 5.0), s.cam.scene_own = 0, camera_changed(s);
            break;
        default:
            break;
        }
        break;
    case SDL_MOUSEBUTTONDOWN:
        if (io.WantCaptureMouse) break;
        if (e.button.button == SDL_BUTTON_LEFT && s.layout == VIEW_LAYOUT_SPLIT &&
            fabs(e.button.x - s.divider * out_w) < 8.0) {
            s.dragging_divider = true;
        } else if (e.button.button == SDL_BUTTON_LEFT || e.button.button == SDL_BUTTON_RIGHT) {
            s.turning = true;
            s.playing = nullptr;
            if (e.button.button == SDL_BUTTON_RIGHT) SDL_SetRelativeMouseMode(SDL_TRUE);
        }
        break;
    case SDL_MOUSEBUTTONUP:
        s.dragging_divider = false;
        if (s.turning) SDL_SetRelativeMouseMode(SDL_FALSE);
        s.turning = false;
        break;
    case SDL_MOUSEMOTION:
        if (!s.turning || !SDL_GetRelativeMouseMode())
            s.mouse_x = e.motion.x, s.mouse_y = e.motion.y;
        if (s.dragging_divider) {
            s.divider = fmin(1.0, fmax(0.0, (double)e.motion.x / (out_w > 0 ? out_w : 1)));
        } else if (s.turning) {
            view_camera_turn(&s.cam, e.motion.xrel * 0.2, -e.motion.yrel * 0.2, s.orbit);
            camera_changed(s);
        }
        break;
    case SDL_MOUSEWHEEL:
        if (io.WantCaptureMouse) break;
        if (s.orbit) {
            view_camera_zoom(&s.cam, pow(0.9, e.wheel.y));
            camera_changed(s);
        } else {
            s.speed = fmin(100.0, fmax(0.05, s.speed * pow(1.25, e.wheel.y)));
        }
        break;
    default:
        break;
    }
}

void fly(state &s, double dt)
{
    if (ImGui::GetIO().WantCaptureKeyboard) return;
    const bool *k = s.held;
    double fwd = (k[SDL_SCANCODE_W] ? 1 : 0) - (k[SDL_SCANCODE_S] ? 1 : 0);
    double right = (k[SDL_SCANCODE_D] ? 1 : 0) - (k[SDL_SCANCODE_A] ? 1 : 0);
    double up = (k[SDL_SCANCODE_E] || k[SDL_SCANCODE_SPACE] ? 1 : 0) -
                (k[SDL_SCANCODE_Q] || k[SDL_SCANCODE_C] ? 1 : 0);
    if (fwd == 0 && right == 0 && up == 0) return;
    double v = s.speed * dt * (k[SDL_SCANCODE_LSHIFT] || k[SDL_SCANCODE_RSHIFT] ? 4.0 : 1.0);
    s.playing = nullptr;
    if (s.orbit) {
        /* Orbit: A/D and W/S turn around the target, Q/E zoom. */
        view_camera_turn(&s.cam, right * 60.0 * dt, fwd * 45.0 * dt, 1);
        if (up != 0) view_camera_zoom(&s.cam, pow(0.5, up * dt));
    } else {
        view_camera_move(&s.cam, fwd * v, right * v, up * v);
    }
    camera_changed(s);
}

SDL_Event key_event(state &s, SDL_Keycode k, bool down)
{
    SDL_Event e;
    memset(&e, 0, sizeof e);
    e.type = down ? SDL_KEYDOWN : SDL_KEYUP;
    e.key.timestamp = SDL_GetTicks();
    e.key.windowID = SDL_GetWindowID(s.window);
    e.key.state = down ? SDL_PRESSED : SDL_RELEASED;
    e.key.keysym.sym = k;
    e.key.keysym.scancode = SDL_GetScancodeFromKey(k);
    return e;
}

SDL_Event mouse_event(state &s, Uint32 type, int x, int y)
{
    SDL_Event e;
    memset(&e, 0, sizeof e);
    e.type = type;
    if (type == SDL_MOUSEMOTION) {
        e.motion.timestamp = SDL_GetTicks();
        e.motion.windowID = SDL_GetWindowID(s.window);
        e.motion.x = x, e.motion.y = y;
        e.motion.xrel = x - s.sc.mouse_x, e.motion.yrel = y - s.sc.mouse_y;
        e.motion.state = s.dragging_divider || s.turning ? SDL_BUTTON_LMASK : 0;
        s.sc.mouse_x = x, s.sc.mouse_y = y;
    } else {
        e.button.timestamp = SDL_GetTicks();
        e.button.windowID = SDL_GetWindowID(s.window);
        e.button.button = SDL_BUTTON_LEFT;
        e.button.state = type == SDL_MOUSEBUTTONDOWN ? SDL_PRESSED : SDL_RELEASED;
        e.button.clicks = 1;
        e.button.x = x, e.button.y = y;
    }
    return e;
}

void later(state &s, int frames, const SDL_Event &e)
{
    s.sc.later.emplace_back(frames, e);
    s.sc.wait = std::max(s.sc.wait, frames + 1);
}

/* Whether the view shows a full-size frame of a camera at rest. */
bool settled(state &s, int out_w, int out_h)
{
    return !s.playing && !s.turning && s.now - s.last_motion >= 0.25 && s.have_frame &&
           s.frame.width == out_w && s.frame.height == out_h && !rendering(s) && !s.reupload;
}

/* Runs the script's actions due this frame, before its events are read. */
void step_script(state &s, bool *quit, int out_w, int out_h)
{
    script &sc = s.sc;
    std::vector<std::pair<int, SDL_Event>> keep;
    for (auto &l : sc.later)
        if (l.first-- <= 0)
            SDL_PushEvent(&l.second);
        else
            keep.push_back(l);
    sc.later.swap(keep);
    if (sc.timing_frames >= 0) sc.timing_frames++;
    if (sc.settling) {
        if (!settled(s, out_w, out_h)) return;
        sc.settling = false;
    }
    if (sc.wait > 0 && --sc.wait > 0) return;
    while (sc.next < sc.actions.size() && sc.wait == 0 && !sc.settling) {
        const action &a = sc.actions[sc.next++];
        const std::string &op = a.op;
        auto num = [&](size_t i) { return atof(a.arg[i].c_str()); };
        if (op == "wait") {
            sc.wait = (int)num(0);
        } else if (op == "key" || op == "hold") {
            SDL_Keycode k = SDL_GetKeyFromName(a.arg[0].c_str());
            SDL_Event down = key_event(s, k, true);
            SDL_PushEvent(&down);
            later(s, a.arg.size() > 1 ? std::max(0, (int)num(1) - 1) : 0, key_event(s, k, false));
        } else if (op == "method") {
            int i = a.arg[0] == "left" ? 0 : 1;
            side_from_spec(&s.ui[i], a.arg[1].c_str());
            update_spec(&s.ui[i], i ? &s.right : &s.left);
        } else if (op == "move") {
            SDL_Event e = mouse_event(s, SDL_MOUSEMOTION, (int)num(0), (int)num(1));
            SDL_PushEvent(&e);
            sc.wait = 1;
        } else if (op == "drag") {
            /* Press, move and release on frames of their own, as a hand would. */
            int y = a.arg.size() > 2 ? (int)num(2) : out_h / 2;
            SDL_Event e = mouse_event(s, SDL_MOUSEMOTION, (int)num(0), y);
            SDL_PushEvent(&e);
            later(s, 0, mouse_event(s, SDL_MOUSEBUTTONDOWN, (int)num(0), y));
            later(s, 1, mouse_event(s, SDL_MOUSEMOTION, (int)num(1), y));
            later(s, 2, mouse_event(s, SDL_MOUSEBUTTONUP, (int)num(1), y));
        } else if (op == "play") {
            char err[512];
            view_path_free(&s.script_path);
            if (!view_path_load(a.arg[0].c_str(), &s.script_path, err, sizeof err)) {
                s.render_error = err;
                *quit = true;
                return;
            }
            start_playing(s, &s.script_path);
        } else if (op == "settle") {
            sc.settling = !settled(s, out_w, out_h);
        } else if (op == "shot" || op == "image") {
            sc.shots.push_back(&a);
            sc.wait = 1;
        } else if (op == "scale") {
            s.move_scale = (float)std::min(1.0, std::max(0.05, num(0)));
        } else if (op == "stats") {
            s.error_stats = a.arg[0] == "on";
        } else if (op == "timing" && a.arg[0] == "start") {
            sc.timing_frames = 0;
            sc.timing_start = seconds();
        } else if (op == "timing") {
            double t = seconds() - sc.timing_start;
            long n = sc.timing_frames;
            if (n > 0 && !s.args->quiet)
                printf("timing: %ld frames of %dx%d (%s) in %.3f s: %.2f ms per frame, %.2f fps\n",
                       n, out_w, out_h, layout_label(s.layout), t, t * 1e3 / (double)n,
                       (double)n / t);
            sc.timing_frames = -1;
        } else if (op == "quit") {
            *quit = true;
            return;
        }
    }
    if (sc.next >= sc.actions.size() && sc.wait == 0 && !sc.settling && sc.later.empty() &&
        sc.shots.empty())
        *quit = true;
}

/* The script's screenshots, once the frame is drawn and before it is shown. */
void script_shots(state &s)
{
    for (const action *a : s.sc.shots) {
        const char *path = a->arg[0].c_str();
        if (a->op == "shot") {
            window_shot(s, path);
        } else if (s.have_frame) {
            persp_image img = {s.frame.width, s.frame.height, (size_t)s.frame.width * 4,
                               s.frame.out};
            persp_status st = persp_image_write_png(s.ui_ctx, path, &img);
            s.status = st == PERSP_OK ? std::string("wrote ") + path
                                      : std::string(path) + ": " + persp_context_error(s.ui_ctx);
        } else {
            s.status = std::string(path) + ": no frame yet";
        }
        if (s.status.compare(0, 6, "wrote ") != 0) s.render_error = s.status;
    }
    s.sc.shots.clear();
}

int run(state &s)
{
    const view_window_args *a = s.args;
    int rc = 0;
    bool quit = false;
    int frames = 0;
    double last = seconds(), avg_dt = 0.0;
    /* A script runs on a clock of its own, 30 frames a second whatever the
     * machine, so that its flights and replays land on the same cameras. */
    const double script_dt = 1.0 / 30.0;
    while (!quit) {
        double real = seconds();
        double dt = real - last;
        last = real;
        if (dt > 0) avg_dt = avg_dt > 0 ? avg_dt * 0.9 + dt * 0.1 : dt;
        s.fps = avg_dt > 0 ? 1.0 / avg_dt : 0.0;
        s.now = s.scripted ? frames * script_dt : real;
        if (s.scripted) dt = script_dt;
        int out_w, out_h;
        SDL_GetRendererOutputSize(s.renderer, &out_w, &out_h);
        /* A script starts once the window shows its first frame: an action
         * on nothing (a screenshot before any frame) would be lost. */
        if (s.scripted && s.have_frame) step_script(s, &quit, out_w, out_h);
        SDL_Event e;
        while (SDL_PollEvent(&e)) {
            ImGui_ImplSDL2_ProcessEvent(&e);
            handle_event(s, e, &quit, out_w);
        }
        ImGui_ImplSDL2_NewFrame();
        ImGui::NewFrame();
        fly(s, dt);
        if (s.playing) {
            double t = s.now - s.play_start + s.playing->keys[0].t;
            view_path_sample(s.playing, t, &s.cam);
            camera_changed(s);
            if (t >= s.playing->keys[s.playing->count - 1].t)
                s.playing = nullptr, s.status = "played";
        }
        if (s.recording && !view_path_add(&s.recorded, s.now - s.record_start, &s.cam))
            toggle_recording(s);
        if (s.panel) panel(s);
        hud(s, out_w);
        int w, h;
        render_size(s, out_w, out_h, &w, &h);
        render_if_needed(s, w, h, a->frames > 0 || s.scripted);
        overlay(s, out_w, out_h);
        magnifier(s, out_w, out_h);
        ImGui::Render();
        SDL_SetRenderDrawColor(s.renderer, 0, 0, 0, 255);
        SDL_RenderClear(s.renderer);
        if (s.texture && s.have_frame) SDL_RenderCopy(s.renderer, s.texture, nullptr, nullptr);
        imgui_sdl_draw(s.renderer, ImGui::GetDrawData());
        if (!s.sc.shots.empty()) script_shots(s);
        bool last_frame = a->frames > 0 && frames + 1 >= a->frames;
        frames++;
        if (last_frame && a->window_shot) {
            window_shot(s, a->window_shot);
            if (s.status.compare(0, 6, "wrote ") != 0) s.render_error = s.status;
        }
        SDL_RenderPresent(s.renderer);
        if (last_frame) break;
        if (s.scripted) continue; /* as fast as it renders */
        /* Leave the cores to the render workers: sleep until an event when
         * idle, briefly while a frame renders, and cap the loop otherwise
         * (without vsync it would spin). */
        bool idle = !s.turning && !s.playing && s.now - s.last_motion > 0.5;
        if (rendering(s))
            SDL_WaitEventTimeout(nullptr, 5);
        else if (idle)
            SDL_WaitEventTimeout(nullptr, 30);
        else if (seconds() - s.now < 0.004)
            SDL_Delay(4);
    }
    if (s.recording) toggle_recording(s);
    if (!a->quiet && !s.status.empty() && a->frames == 0) printf("%s\n", s.status.c_str());
    /* Interactively a failed configuration was shown in the HUD and could be
     * changed; a fixed run of frames has nobody watching. */
    if (!s.render_error.empty() && (a->frames > 0 || s.scripted)) {
        fprintf(stderr, "persp: view: %s\n", s.render_error.c_str());
        rc = 1;
    }
    return rc;
}

} // namespace

/* SDL's video and events on a real display: 0, or 1 after the message. */
static int sdl_start(void)
{
    const char *asked = getenv("SDL_VIDEODRIVER");
#if defined(__linux__)
    /* No X11 or Wayland display and no driver asked for: said before SDL
     * starts, as SDL's own Wayland probe would first print "error:
     * XDG_RUNTIME_DIR is invalid" and then fall back to the offscreen
     * driver refused below. */
    const char *x11 = getenv("DISPLAY"), *wayland = getenv("WAYLAND_DISPLAY");
    if ((!asked || !asked[0]) && !(x11 && x11[0]) && !(wayland && wayland[0])) {
        fprintf(stderr, "persp: view: cannot open a window: no display (DISPLAY and WAYLAND_DISPLAY "
                        "are unset); --play renders camera paths without one, SDL_VIDEODRIVER=offscreen "
                        "runs the window invisibly\n");
        return 1;
    }
#endif
    if (SDL_Init(SDL_INIT_VIDEO | SDL_INIT_EVENTS) != 0) {
        fprintf(stderr,
                "persp: view: cannot open a window: %s (SDL_VIDEODRIVER=%s); "
                "--play renders camera paths without one\n",
                SDL_GetError(), getenv("SDL_VIDEODRIVER") ? getenv("SDL_VIDEODRIVER") : "unset");
        return 1;
    }
    /* Without a display SDL 2 falls back to its offscreen driver by itself,
     * and the window then runs invisibly until killed. Those drivers are
     * for a caller who asks for them (SDL_VIDEODRIVER, as the tests do). */
    const char *driver = SDL_GetCurrentVideoDriver();
    if (driver && (!asked || !asked[0]) && (!strcmp(driver, "offscreen") || !strcmp(driver, "dummy"))) {
        const char *display = getenv("DISPLAY");
        fprintf(stderr,
                "persp: view: cannot open a window: no display could be opened (DISPLAY=%s); "
                "--play renders camera paths without one, SDL_VIDEODRIVER=offscreen runs the "
                "window invisibly\n",
                display && display[0] ? display : "unset");
        SDL_Quit();
        return 1;
    }
    SDL_SetHint(SDL_HINT_RENDER_SCALE_QUALITY, "0");
    return 0;
}

/* SDL installs its own SIGINT/SIGTERM handlers (the quit event, so a
 * screenshot being written is finished before the window closes) unless
 * SDL_HINT_NO_SIGNAL_HANDLERS is set; then the signals would kill the
 * process in the middle of a write and leave its temporary file. There
 * the CLI's handlers come back, which remove it (POSIX sigaction() with a
 * NULL act only reads the action). */
static void keep_signal_handlers(const view_window_args *args)
{
    struct sigaction on_int, on_term;
    if (args->install_signal_handlers && sigaction(SIGINT, nullptr, &on_int) == 0 &&
        sigaction(SIGTERM, nullptr, &on_term) == 0 && on_int.sa_handler == SIG_DFL &&
        on_term.sa_handler == SIG_DFL)
        args->install_signal_handlers();
}

/* The window and its renderer: true, or false after the message. */
static bool open_window(state &s, const view_window_args *args)
{
    char title[256];
    snprintf(title, sizeof title, "persp view - %s", args->scene_name);
    s.window = SDL_CreateWindow(title, SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED, args->width,
                                args->height, SDL_WINDOW_RESIZABLE);
    if (s.window)
        s.renderer =
            SDL_CreateRenderer(s.window, -1, SDL_RENDERER_ACCELERATED | SDL_RENDERER_PRESENTVSYNC);
    /* The dummy and offscreen drivers have no accelerated renderer; the
     * software one is there everywhere. */
    if (s.window && !s.renderer)
        s.renderer = SDL_CreateRenderer(s.window, -1, SDL_RENDERER_SOFTWARE);
    if (s.window && s.renderer) return true;
    fprintf(stderr, "persp: view: cannot open a window: %s\n", SDL_GetError());
    if (s.window) SDL_DestroyWindow(s.window);
    return false;
}

static void imgui_start(state &s)
{
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiIO &io = ImGui::GetIO();
    io.IniFilename = nullptr; /* no imgui.ini left in the working folder */
    for (const char *f : font_paths)
        if (access(f, R_OK) == 0) {
            io.Fonts->AddFontFromFileTTF(f, 15.0f);
            break;
        }
    ImGui::StyleColorsDark();
    ImGui_ImplSDL2_InitForSDLRenderer(s.window);
}

/* The settings, camera and scenes of the arguments into s. */
static void session_state(state &s, const view_window_args *args)
{
    s.scripted = args->script != nullptr;
    s.left = args->left;
    s.right = args->right;
    s.layout = args->layout;
    s.divider = args->divider;
    s.heat_max = args->heat_max;
    persp_scene_info info;
    persp_scene_get_info(args->scene, &info);
    side_from_spec(&s.ui[0], s.left.method[0] ? s.left.method : info.method);
    side_from_spec(&s.ui[1], s.right.method);
    view_camera_from_scene(&s.home, args->scene, args->width, args->height);
    s.cam = s.home;
    s.wk.ctx = args->ctx;
    s.wk.scenes = view_scenes{args->scene, args->tinted, args->coords};
}

/* The render thread beside the event loop, until the window closes. */
static int session(state &s, const view_window_args *args)
{
    std::string err;
    if (args->script && !load_script(args->script, &s.sc, &err)) {
        fprintf(stderr, "persp: view: %s\n", err.c_str());
        return 1;
    }
    session_state(s, args);
    s.wk.lock = SDL_CreateMutex();
    s.wk.wake = SDL_CreateCond();
    s.wk.done = SDL_CreateCond();
    if (persp_context_create(nullptr, &s.ui_ctx) == PERSP_OK && args->temp_file)
        persp_context_set_temp_file_handler(s.ui_ctx, args->temp_file, nullptr);
    int rc = 1;
    if (!s.ui_ctx || !s.wk.lock || !s.wk.wake || !s.wk.done ||
        !(s.wk.thread = SDL_CreateThread(worker_main, "persp render", &s.wk))) {
        fprintf(stderr, "persp: view: cannot start the render thread: %s\n", SDL_GetError());
    } else {
        rc = run(s);
        SDL_LockMutex(s.wk.lock);
        s.wk.quit = true;
        SDL_CondSignal(s.wk.wake);
        SDL_UnlockMutex(s.wk.lock);
        SDL_WaitThread(s.wk.thread, nullptr);
    }
    return rc;
}

static void close_window(state &s)
{
    for (view_frame &f : s.wk.frames)
        view_frame_free(&f);
    if (s.wk.done) SDL_DestroyCond(s.wk.done);
    if (s.wk.wake) SDL_DestroyCond(s.wk.wake);
    if (s.wk.lock) SDL_DestroyMutex(s.wk.lock);
    persp_context_destroy(s.ui_ctx);
    view_path_free(&s.recorded);
    view_path_free(&s.script_path);
    view_frame_free(&s.frame);
    imgui_sdl_draw_shutdown();
    ImGui_ImplSDL2_Shutdown();
    ImGui::DestroyContext();
    if (s.texture) SDL_DestroyTexture(s.texture);
    SDL_DestroyRenderer(s.renderer);
    SDL_DestroyWindow(s.window);
    SDL_Quit();
}

extern "C" int view_window_run(const view_window_args *args)
{
    if (sdl_start() != 0) return 1;
    keep_signal_handlers(args);
    state s;
    s.args = args;
    if (!open_window(s, args)) {
        SDL_Quit();
        return 1;
    }
    imgui_start(s);
    int rc = 1;
    if (!imgui_sdl_draw_init(s.renderer))
        fprintf(stderr, "persp: view: cannot create the font texture: %s\n", SDL_GetError());
    else
        rc = session(s, args);
    close_window(s);
    return rc;
}
