import { defineConfig } from 'vite';

// Built into web/dist, which `uavcover serve --static web/dist` serves at /.
// `npm run dev` proxies the API and the map tiles (/tiles) to a server on :8080.
export default defineConfig({
  base: '/',
  build: { outDir: 'dist', emptyOutDir: true, sourcemap: false, chunkSizeWarningLimit: 800 },
  server: { proxy: { '/api': { target: 'http://127.0.0.1:8080', ws: true }, '/tiles': { target: 'http://127.0.0.1:8080' } } },
});
