/* Dear ImGui draw lists through SDL_Renderer. Debian's libimgui ships the
 * SDL2 platform backend compiled but not the SDL_Renderer one, so persp
 * carries this small renderer (SDL_RenderGeometryRaw, SDL >= 2.0.18). */
#ifndef PERSP_IMGUI_SDL_DRAW_H
#define PERSP_IMGUI_SDL_DRAW_H

#include <SDL.h>
#include <imgui.h>

/* Uploads the font atlas; false if SDL cannot make the texture. */
bool imgui_sdl_draw_init(SDL_Renderer *renderer);
void imgui_sdl_draw_shutdown();
void imgui_sdl_draw(SDL_Renderer *renderer, ImDrawData *data);

#endif
