/// <reference types="vitest/config" />
import react from "@vitejs/plugin-react";
import { defineConfig } from "vite";

// The app is served by FastAPI from frontend/dist at "/" (index.html for every non-/api path).
// `npm run dev` proxies /api to a backend started with `countersign serve` on port 8000.
export default defineConfig({
  base: "/",
  plugins: [react()],
  build: {
    outDir: "dist",
    emptyOutDir: true,
    sourcemap: false,
    assetsDir: "assets",
  },
  server: {
    proxy: {
      "/api": { target: process.env.COUNTERSIGN_API ?? "http://127.0.0.1:8000", changeOrigin: false },
    },
  },
  test: {
    include: ["src/**/*.test.ts"],
    environment: "node",
  },
});
