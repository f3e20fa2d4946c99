FROM node:20-slim AS frontend
WORKDIR /src/frontend
COPY frontend/package.json frontend/package-lock.json ./
RUN npm ci
COPY frontend ./
RUN npm run build

FROM python:3.11-slim
WORKDIR /app
COPY pyproject.toml README.md ./
COPY backend ./backend
COPY migrations ./migrations
COPY ontology ./ontology
RUN pip install --no-cache-dir -e .
COPY --from=frontend /src/frontend/dist ./frontend/dist
ENV COUNTERSIGN_DATA_DIR=/data
VOLUME ["/data"]
EXPOSE 8000
CMD ["countersign", "serve", "--host", "0.0.0.0", "--port", "8000", "--data-dir", "/data"]
