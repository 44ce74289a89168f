#pragma once
// Procedural hair strands for alpha cards. MakeHuman's hair and eyebrow proxies are layers of
// cards drawn, in MakeHuman, with a strand texture whose alpha cuts them into strands; the CC0
// assets come without it, so the cards render as an opaque helmet. Here strands run along a
// card's v, `per_uv` of them per UV unit across u, each of its own width and shade, gently
// waving; a ray that meets a card between strands passes through (an Embree filter), so light
// and the layers beneath show between them. Pure arithmetic on the UV (no libm), so every ISA
// and thread count draws the same strands.

namespace wheelpose::render {

struct StrandSample {
  bool covered = false;  // on a strand (else the card is transparent here)
  float shade = 1.0f;    // multiplies the hair colour: strands differ, edges are darker
};

// The strand pattern at (u, v); `coverage` (0–1) is the mean share of the card strands cover.
StrandSample strand_at(float u, float v, float per_uv, float coverage);

}  // namespace wheelpose::render
