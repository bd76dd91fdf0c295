#include "dm_viewer_ui.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "imgui.h"
#include "imgui_impl_glfw.h"
#include "imgui_impl_opengl3.h"

extern "C" {
#include "render/dm_render_legend.h"
#include "render/dm_render_plan.h"
}

bool dm_ui_init(GLFWwindow *window)
{
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiIO &io = ImGui::GetIO();
    io.IniFilename = NULL; /* no imgui.ini next to the user's files */
    ImGui::StyleColorsDark();
    ImGui::GetStyle().WindowRounding = 4.0f;
    if (!ImGui_ImplGlfw_InitForOpenGL(window, true)) return false;
    return ImGui_ImplOpenGL3_Init("#version 330 core");
}

void dm_ui_shutdown(void)
{
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
}

bool dm_ui_wants_mouse(void) { return ImGui::GetIO().WantCaptureMouse; }
bool dm_ui_wants_keyboard(void) { return ImGui::GetIO().WantCaptureKeyboard; }

static void section_light(dm_viewer *v)
{
    dm_scene *s = &v->scene;
    if (s->light_count == 0) {
        ImGui::TextUnformatted("(no lights)");
        return;
    }
    char label[64];
    snprintf(label, sizeof label, "light %d (%s)", v->light, dm_light_type_name(s->lights[v->light].type));
    if (ImGui::BeginCombo("light", label)) {
        for (int i = 0; i < s->light_count; ++i) {
            snprintf(label, sizeof label, "light %d (%s)", i, dm_light_type_name(s->lights[i].type));
            if (ImGui::Selectable(label, i == v->light)) v->light = i;
        }
        ImGui::EndCombo();
    }
    dm_light *l = &s->lights[v->light];
    if (ImGui::SliderFloat("intensity", &l->intensity, 0.0f, 10.0f, "%.2f")) v->dirty = true;
    if (ImGui::ColorEdit3("colour", l->color, ImGuiColorEditFlags_Float)) v->dirty = true;
    ImGui::TextDisabled("shift + left drag moves it");
    if (ImGui::Checkbox("rotate around the head (R)", &v->light_rotating)) v->dirty = true;
    ImGui::SliderFloat("deg/s", &v->rotate_deg_per_s, 5.0f, 180.0f, "%.0f");
    if (ImGui::SliderFloat("azimuth", &v->light_rotation_deg, -360.0f, 360.0f, "%.1f deg")) v->dirty = true;
}

/* The live physical skin (dm_viewer_skin.h): the weights refitted per change. */
static void section_skin(dm_viewer *v)
{
    if (!v->skin.available) return;
    ImGui::Separator();
    ImGui::TextUnformatted(v->skin.from_pack ? "skin (the pack's)" : "skin (from the Caucasian exemplar)");
    float m = (float)v->skin.now.melanin_fraction, b = (float)v->skin.now.blood_fraction,
          e = (float)v->skin.now.epidermis_mm;
    if (ImGui::SliderFloat("melanin", &m, 0.0f, 0.5f, "%.4f", ImGuiSliderFlags_Logarithmic))
        dm_viewer_skin_set(v, "melanin", m);
    if (ImGui::SliderFloat("blood", &b, 0.0f, 0.1f, "%.4f", ImGuiSliderFlags_Logarithmic))
        dm_viewer_skin_set(v, "blood", b);
    if (ImGui::SliderFloat("epidermis", &e, 0.001f, 2.0f, "%.3f mm", ImGuiSliderFlags_Logarithmic))
        dm_viewer_skin_set(v, "epidermis", e);
    if (v->skin.ms_count)
        ImGui::Text("refit + hand-over: median %.2f ms over %d changes", dm_viewer_skin_median_ms(v), v->skin.ms_count);
}

static void section_effects(dm_viewer *v)
{
    for (int e = 0; e < DM_EFFECT_COUNT; ++e) {
        bool on = v->scene.effects[e];
        char label[64];
        snprintf(label, sizeof label, "%d  %s", e + 1, dm_effect_name((dm_effect)e));
        if (ImGui::Checkbox(label, &on)) dm_viewer_set_effect(v, (dm_effect)e, on);
    }
    const char *tech = dm_sss_technique_name(v->scene.sss_technique);
    if (ImGui::BeginCombo("technique (T)", tech)) {
        for (int k = 0; k < DM_SSS_TECHNIQUE_COUNT; ++k)
            if (dm_sss_technique_available((dm_sss_technique)k) && !dm_viewer_technique_missing(v, (dm_sss_technique)k) &&
                ImGui::Selectable(dm_sss_technique_name((dm_sss_technique)k), k == (int)v->scene.sss_technique))
                dm_viewer_set_technique(v, dm_sss_technique_name((dm_sss_technique)k));
        ImGui::EndCombo();
    }
    bool split = v->tsplit;
    if (ImGui::Checkbox("beside the other technique (shift+T)", &split)) dm_viewer_set_technique_split(v, split);
    if (v->tsplit) {
        if (v->cmp.layout == DM_REFCMP_SPLIT && ImGui::SliderFloat("divider", &v->cmp.split, 0.0f, 1.0f, "%.2f"))
            v->dirty = true;
        if (v->cmp.has_stats) ImGui::TextWrapped("left/reference: the other technique\n%s", v->cmp.text);
    }
    if (ImGui::SliderFloat("exposure", &v->scene.exposure, -6.0f, 6.0f, "%.2f stops")) v->dirty = true;
    if (ImGui::SliderFloat("blur width", &v->blur_scale, 0.1f, 10.0f, "x%.2f variance",
                           ImGuiSliderFlags_Logarithmic))
        v->dirty = true;
    if (ImGui::SliderFloat("mix", &v->scene.mix, 0.0f, 1.0f, "%.2f pre-scatter")) v->dirty = true;
    if (ImGui::SliderFloat("roughness", &v->roughness_scale, 0.1f, 4.0f, "x%.2f", ImGuiSliderFlags_Logarithmic))
        v->dirty = true;
    static const int sizes[] = {128, 256, 512, 1024, 2048};
    char cur[32];
    snprintf(cur, sizeof cur, "%d", v->irradiance_size);
    if (ImGui::BeginCombo("irradiance", cur)) {
        for (int i = 0; i < 5; ++i) {
            char t[16];
            snprintf(t, sizeof t, "%d", sizes[i]);
            if (ImGui::Selectable(t, sizes[i] == v->irradiance_size)) dm_viewer_set_irradiance(v, sizes[i]);
        }
        ImGui::EndCombo();
    }
    section_skin(v);
}

static void section_view(dm_viewer *v)
{
    char cur[16];
    dm_viewer_view_text(v, cur, sizeof cur);
    if (ImGui::BeginCombo("debug view (V)", cur)) {
        for (int i = 0; i < v->view_count; ++i)
            if (ImGui::Selectable(v->view_names[i], !strcmp(cur, v->view_names[i])))
                dm_viewer_set_view(v, v->view_names[i]);
        ImGui::EndCombo();
    }
    if (ImGui::SliderFloat("view scale", &v->view_scale, 0.01f, 100.0f, "x%.2f", ImGuiSliderFlags_Logarithmic))
        v->dirty = true;
    /* the stretch and curvature views' colour scale, the specular view's gain */
    float lo = 0, hi = 0;
    const char *quantity = NULL;
    if (v->r) dm_renderer_view_scale(v->r, &lo, &hi, &quantity);
    if (quantity) {
        ImDrawList *dl = ImGui::GetWindowDrawList();
        ImVec2 at = ImGui::GetCursorScreenPos();
        float w = ImGui::GetContentRegionAvail().x, h = ImGui::GetTextLineHeight();
        for (int i = 0; i < 64; ++i) {
            uint8_t c[3];
            dm_render_turbo((i + 0.5) / 64.0, c);
            dl->AddRectFilled(ImVec2(at.x + w * i / 64, at.y), ImVec2(at.x + w * (i + 1) / 64 + 1, at.y + h),
                              IM_COL32(c[0], c[1], c[2], 255));
        }
        ImGui::Dummy(ImVec2(w, h));
        ImGui::Text("%.3g .. %.3g  %s", lo, hi, quantity);
    } else if (v->r && v->view == DM_VIEW_SPECULAR) {
        ImGui::Text("head x %.3g (99th percentile to white)", dm_renderer_view_gain(v->r));
    }
}

static void section_environment(dm_viewer *v)
{
    dm_scene *s = &v->scene;
    char name[256];
    dm_viewer_env_name(v, v->env, name, (int)sizeof name);
    if (ImGui::BeginCombo("map", name[0] ? name : "(none)")) { /* every packed environment */
        for (int k = 0; k < (v->env_count > 0 ? v->env_count : 1); ++k) { /* synthetic: its one map */
            char item[280];
            dm_viewer_env_name(v, k, name, (int)sizeof name);
            snprintf(item, sizeof item, "%s##env%d", name[0] ? name : "(unnamed)", k);
            if (ImGui::Selectable(item, k == v->env) && k != v->env) dm_viewer_set_env(v, k);
        }
        ImGui::EndCombo();
    }
    if (ImGui::SliderFloat("env intensity", &s->env_intensity, 0.0f, 4.0f, "%.2f")) v->dirty = true;
    if (ImGui::SliderFloat("env rotation", &s->env_rotation_deg, -180.0f, 180.0f, "%.0f deg")) v->dirty = true;
    bool bg = s->env_background;
    if (ImGui::Checkbox("background (B)", &bg)) dm_viewer_set_background(v, bg);
}

static void section_reference(dm_viewer *v)
{
    dm_viewer_compare *c = &v->cmp;
    ImGui::TextWrapped("%s (%s, %dx%d)", c->path, dm_refcmp_mode_name(c->ref.mode), c->ref.width, c->ref.height);
    static const char *modes[] = {"side", "split", "error", "off"};
    int cur = c->on ? (int)c->layout : 3;
    if (ImGui::BeginCombo("compare (C)", modes[cur])) {
        for (int i = 0; i < 4; ++i)
            if (ImGui::Selectable(modes[i], i == cur)) dm_viewer_set_compare(v, modes[i]);
        ImGui::EndCombo();
    }
    if (c->layout == DM_REFCMP_SPLIT && ImGui::SliderFloat("divider", &c->split, 0.0f, 1.0f, "%.2f")) v->dirty = true;
    if (ImGui::SliderFloat("error scale", &c->error_scale, 0.001f, 1.0f, "%.3f", ImGuiSliderFlags_Logarithmic))
        v->dirty = true;
    if (c->on && c->has_stats) ImGui::TextWrapped("%s", c->text);
}

static void section_timings(dm_viewer *v)
{
    const dm_render_plan *plan = v->r ? dm_renderer_plan(v->r) : NULL;
    ImGui::Text("frame %.1f ms  (%d frames; UI %.1f ms)", v->frame_ms, v->frames, v->ui_ms);
    if (!plan || !ImGui::BeginTable("passes", 2, ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingStretchProp)) return;
    for (int i = 0; i < plan->pass_count; ++i) {
        ImGui::TableNextRow();
        ImGui::TableSetColumnIndex(0);
        ImGui::TextUnformatted(plan->passes[i].name);
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", plan->passes[i].why);
        ImGui::TableSetColumnIndex(1);
        ImGui::Text("%7.2f ms", v->pass_ms[i]);
    }
    ImGui::EndTable();
    ImGui::TextDisabled("%s", v->r && dm_renderer_timing_on_cpu(v->r) ? "CPU clock around glFinish" : "GL timer queries");
}

static void panel(dm_viewer *v, float w, float h)
{
    const float pw = 330.0f;
    ImGui::SetNextWindowPos(ImVec2(w - pw - 8.0f, 8.0f), ImGuiCond_Once);
    ImGui::SetNextWindowSize(ImVec2(pw, h - 16.0f), ImGuiCond_Once);
    /* a window under three panel widths would be mostly panel: start collapsed to its
     * title bar there (click it, or H hides it), so the head is seen first */
    ImGui::SetNextWindowCollapsed(w < 3.0f * pw, ImGuiCond_Once);
    ImGui::SetNextWindowBgAlpha(0.82f);
    if (!ImGui::Begin("dermis-view", NULL, 0)) {
        ImGui::End();
        return;
    }
    ImGui::PushItemWidth(170.0f);
    ImGui::TextWrapped("%s", v->opt.pack ? v->opt.pack : "synthetic sphere");
    ImGui::TextDisabled("%dx%d on %s", v->opt.width, v->opt.height, v->r ? dm_renderer_gl_name(v->r) : "-");
    if (v->status[0]) ImGui::TextWrapped("%s", v->status);
    if (ImGui::CollapsingHeader("Camera", ImGuiTreeNodeFlags_DefaultOpen)) {
        ImGui::Text("yaw %.0f  pitch %.0f  distance %.2f", v->yaw_deg, v->pitch_deg, v->distance);
        if (ImGui::Button("reset (space)")) dm_viewer_reset_camera(v);
        ImGui::SameLine();
        if (ImGui::Button("help (F1)")) v->show_help = !v->show_help;
        ImGui::SameLine();
        if (ImGui::Button("screenshot (S)")) {
            char name[64];
            dm_viewer_next_shot_name(v, name, sizeof name);
            dm_viewer_screenshot(v, name);
        }
    }
    if (ImGui::CollapsingHeader("Light", ImGuiTreeNodeFlags_DefaultOpen)) section_light(v);
    if (ImGui::CollapsingHeader("Effects", ImGuiTreeNodeFlags_DefaultOpen)) section_effects(v);
    if (v->cmp.loaded && ImGui::CollapsingHeader("Reference", ImGuiTreeNodeFlags_DefaultOpen)) section_reference(v);
    if (ImGui::CollapsingHeader("Debug view", ImGuiTreeNodeFlags_DefaultOpen)) section_view(v);
    if (ImGui::CollapsingHeader("Environment", ImGuiTreeNodeFlags_DefaultOpen)) section_environment(v);
    if (ImGui::CollapsingHeader("Timings", ImGuiTreeNodeFlags_DefaultOpen)) section_timings(v);
    if (dm_viewer_shows_head(v)) {
        ImGui::Separator();
        ImGui::TextWrapped("%s", dm_viewer_attribution);
    }
    ImGui::PopItemWidth();
    ImGui::End();
}

void dm_ui_frame(dm_viewer *v)
{
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    ImVec2 ds = ImGui::GetIO().DisplaySize;
    /* the picture, rows bottom-up: flip v */
    ImGui::GetBackgroundDrawList()->AddImage((ImTextureID)(intptr_t)v->tex, ImVec2(0, 0),
                                             ImVec2((float)v->opt.width, (float)v->opt.height), ImVec2(0, 1),
                                             ImVec2(1, 0));
    if (v->show_panel) panel(v, ds.x, ds.y);
    if (v->show_help) {
        ImGui::SetNextWindowPos(ImVec2(ds.x * 0.5f, ds.y * 0.5f), ImGuiCond_Always, ImVec2(0.5f, 0.5f));
        ImGui::SetNextWindowBgAlpha(0.9f);
        ImGui::Begin("keys", &v->show_help,
                     ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoMove);
        ImGui::TextUnformatted(dm_viewer_help);
        ImGui::End();
    }
    if (dm_viewer_shows_head(v)) {
        ImDrawList *dl = ImGui::GetForegroundDrawList();
        ImVec2 at(8.0f, ds.y - ImGui::GetTextLineHeight() - 6.0f);
        dl->AddText(ImVec2(at.x + 1, at.y + 1), IM_COL32(0, 0, 0, 200), dm_viewer_attribution);
        dl->AddText(at, IM_COL32(235, 235, 235, 255), dm_viewer_attribution);
    }
    ImGui::Render();
}

void dm_ui_render(void) { ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData()); }
