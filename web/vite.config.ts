import { defineConfig } from 'vitest/config';

// Served by mobotd from web/dist at "/"; relative asset paths keep it working behind a prefix too.
export default defineConfig({
  base: './',
  build: {
    outDir: 'dist',
    emptyOutDir: true,
    target: 'es2022',
    sourcemap: false,
    // The main chunk is ~90 kB; the 3D page's chunk (three.js WebGLRenderer + OrbitControls, loaded
    // only when the 3D tab opens) is ~550 kB. Past this limit something grew that should not have.
    chunkSizeWarningLimit: 600,
  },
  server: {
    // `npm run dev` talks to a local mobotd (REST + WebSocket) on :8080.
    proxy: {
      '/api': { target: 'http://127.0.0.1:8080', ws: true },
      '/metrics': 'http://127.0.0.1:8080',
    },
  },
  test: {
    include: ['test/**/*.test.ts'],
    environment: 'node',
  },
});
