#include "imgui_sdl_draw.h"

#include <stdint.h>

static SDL_Texture *font_texture;

bool imgui_sdl_draw_init(SDL_Renderer *renderer)
{
    ImGuiIO &io = ImGui::GetIO();
    io.BackendRendererName = "persp_sdl_renderer";
    io.BackendFlags |= ImGuiBackendFlags_RendererHasVtxOffset;
    unsigned char *pixels = nullptr;
    int w = 0, h = 0;
    io.Fonts->GetTexDataAsRGBA32(&pixels, &w, &h);
    /* ABGR8888 is R, G, B, A bytes in memory on little-endian machines,
     * the order ImGui's atlas uses. */
    font_texture =
        SDL_CreateTexture(renderer, SDL_PIXELFORMAT_ABGR8888, SDL_TEXTUREACCESS_STATIC, w, h);
    if (!font_texture) return false;
    SDL_UpdateTexture(font_texture, nullptr, pixels, 4 * w);
    SDL_SetTextureBlendMode(font_texture, SDL_BLENDMODE_BLEND);
    SDL_SetTextureScaleMode(font_texture, SDL_ScaleModeLinear);
    io.Fonts->SetTexID((ImTextureID)(intptr_t)font_texture);
    return true;
}

void imgui_sdl_draw_shutdown()
{
    if (font_texture) SDL_DestroyTexture(font_texture);
    font_texture = nullptr;
    ImGui::GetIO().Fonts->SetTexID(0);
}

void imgui_sdl_draw(SDL_Renderer *renderer, ImDrawData *data)
{
    ImVec2 off = data->DisplayPos;
    for (int n = 0; n < data->CmdListsCount; n++) {
        const ImDrawList *list = data->CmdLists[n];
        const ImDrawVert *vtx = list->VtxBuffer.Data;
        const ImDrawIdx *idx = list->IdxBuffer.Data;
        for (int c = 0; c < list->CmdBuffer.Size; c++) {
            const ImDrawCmd *cmd = &list->CmdBuffer[c];
            if (cmd->UserCallback) {
                if (cmd->UserCallback != ImDrawCallback_ResetRenderState)
                    cmd->UserCallback(list, cmd);
                continue;
            }
            float x0 = cmd->ClipRect.x - off.x, y0 = cmd->ClipRect.y - off.y;
            float x1 = cmd->ClipRect.z - off.x, y1 = cmd->ClipRect.w - off.y;
            if (x1 <= x0 || y1 <= y0) continue;
            SDL_Rect clip = {(int)x0, (int)y0, (int)(x1 - x0), (int)(y1 - y0)};
            SDL_RenderSetClipRect(renderer, &clip);
            const ImDrawVert *v = vtx + cmd->VtxOffset;
            SDL_RenderGeometryRaw(renderer, (SDL_Texture *)(intptr_t)cmd->GetTexID(), &v->pos.x,
                                  (int)sizeof(ImDrawVert), (const SDL_Color *)&v->col,
                                  (int)sizeof(ImDrawVert), &v->uv.x, (int)sizeof(ImDrawVert),
                                  list->VtxBuffer.Size - (int)cmd->VtxOffset, idx + cmd->IdxOffset,
                                  (int)cmd->ElemCount, (int)sizeof(ImDrawIdx));
        }
    }
    SDL_RenderSetClipRect(renderer, nullptr);
}
